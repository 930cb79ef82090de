// The image-parallel render across the ranks of an MPI job (the scene is
// loaded and its BVH built on every rank). Rank 0 hands out tiles to whichever
// rank asks next and renders tiles itself in between, so a slow rank or an
// expensive part of the image takes fewer tiles; every other rank renders the
// tiles it is given and sends their pixels back.
#pragma once

#include <atomic>
#include <functional>

#include "io/tile_set.h"
#include "mpi_job.h"
#include "region_renderer.h"

namespace pt::dist {

struct TileWork {
  RegionRenderer render;
  RenderSettings settings;
  TileGrid grid;
  const std::atomic<bool>* cancel = nullptr;  ///< stop signal of this rank
};

/// Rank 0: `set` holds the tiles already finished (a checkpoint's) and gets
/// every tile finished here; `after_tile(set)` runs after each new tile, one
/// call at a time. Returns false if `cancel` stopped the render (rank 0 stops
/// handing out tiles and returns at once; the caller ends the job). Other
/// ranks: renders until rank 0 has no more tiles; `set` is untouched.
bool render_across_ranks(const MpiJob& job, const TileWork& work, TileSet& set,
                         const std::function<void(const TileSet&)>& after_tile);

}  // namespace pt::dist
