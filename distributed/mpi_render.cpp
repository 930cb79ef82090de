// render_across_ranks with Open MPI. Messages (all on MPI_COMM_WORLD):
//   rank k -> 0  kAsk      nothing: "give me a tile" (the first request)
//   rank k -> 0  kResult   a finished tile (append_tile) and its RenderStats,
//                          which is also the request for the next tile
//   0 -> rank k  kTile     the tile number to render
//   0 -> rank k  kNoMore   no tiles are left: rank k is done
// Rank 0 answers from a second thread that polls with MPI_Iprobe and sleeps
// between polls, so it takes almost no time from the tiles rank 0 renders.
#include "mpi_render.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "io/binary_io.h"
#include "tile_render.h"

namespace pt::dist {
namespace {

enum Tag : int { kAsk = 1, kResult = 2, kTile = 3, kNoMore = 4 };

/// Tiles not yet handed out, shared by rank 0's two threads.
class TileQueue {
 public:
  TileQueue(const TileGrid& grid, const TileSet& done) : done_(grid.count(), false) {
    for (const TilePixels& t : done.tiles) done_[t.tile] = true;
  }
  /// The next tile nobody has, or -1.
  int64_t next() {
    std::lock_guard lock(mutex_);
    while (next_ < done_.size() && done_[next_]) ++next_;
    return next_ < done_.size() ? int64_t(next_++) : -1;
  }

 private:
  std::mutex mutex_;
  std::vector<bool> done_;
  size_t next_ = 0;
};

/// Rank 0's store of finished tiles.
class Collector {
 public:
  Collector(TileSet& set, const std::function<void(const TileSet&)>& after) : set_(set), after_(after) {}
  void add(TilePixels&& t, const RenderStats& stats) {
    std::lock_guard lock(mutex_);
    set_.tiles.push_back(std::move(t));
    set_.stats.add_render(stats);
    if (after_) after_(set_);
  }

 private:
  std::mutex mutex_;
  TileSet& set_;
  const std::function<void(const TileSet&)>& after_;
};

void send_tile_number(int rank, int64_t t) {
  if (t < 0) {
    MPI_Send(nullptr, 0, MPI_BYTE, rank, kNoMore, MPI_COMM_WORLD);
  } else {
    uint32_t n = uint32_t(t);
    MPI_Send(&n, 1, MPI_UINT32_T, rank, kTile, MPI_COMM_WORLD);
  }
}

/// Rank 0's second thread: answers every request until each other rank has
/// been told there are no more tiles, or rank 0 is stopped or failed. Throws
/// if a rank sends something other than the tile it was given.
void serve_tiles(const MpiJob& job, const TileWork& work, TileQueue& queue, Collector& collector,
                 const std::atomic<bool>& failed) {
  int ranks_working = job.size() - 1;
  std::vector<int64_t> given(size_t(job.size()), -1);  // the tile each rank is rendering
  std::string buffer;
  while (ranks_working > 0) {
    if ((work.cancel && work.cancel->load()) || failed.load()) return;
    int waiting = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
    if (!waiting) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    buffer.resize(size_t(bytes));
    MPI_Recv(buffer.data(), bytes, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (status.MPI_TAG == kResult) {
      std::string_view in(buffer);
      TilePixels tile;
      RenderStats stats;
      if (!take_tile(in, work.grid, uint32_t(work.settings.samples_per_pixel), tile) || !take_stats(in, stats) ||
          !in.empty() || int64_t(tile.tile) != given[size_t(status.MPI_SOURCE)])
        throw std::runtime_error("rank " + std::to_string(status.MPI_SOURCE) +
                                 " sent a result that is not the tile it was given; ending the job");
      collector.add(std::move(tile), stats);
    }
    int64_t next = queue.next();
    given[size_t(status.MPI_SOURCE)] = next;
    send_tile_number(status.MPI_SOURCE, next);
    if (next < 0) --ranks_working;
  }
}

/// Rank k > 0: asks for tiles and renders them until told there are no more.
void work_for_rank0(const MpiJob& job, const TileWork& work) {
  MPI_Send(nullptr, 0, MPI_BYTE, 0, kAsk, MPI_COMM_WORLD);
  std::string message;
  for (;;) {
    uint32_t t = 0;
    MPI_Status status;
    MPI_Recv(&t, 1, MPI_UINT32_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
    if (status.MPI_TAG == kNoMore) return;
    std::optional<RenderedTile> tile = render_tile(work.render, work.settings, work.grid, t, work.cancel);
    if (!tile) {
      // Stopped by a signal. When mpirun stops the whole job it kills this
      // rank within a second (odls_base_sigkill_timeout) while rank 0 writes
      // what is done; if the signal was for this rank alone, end the job.
      std::this_thread::sleep_for(std::chrono::seconds(3));
      std::fprintf(stderr, "error: rank %d of %d was stopped by a signal; ending the job\n", job.rank(), job.size());
      job.abort(1);
    }
    message.clear();
    append_tile(message, tile->pixels);
    append_stats(message, tile->stats);
    MPI_Send(message.data(), int(message.size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
  }
}

}  // namespace

bool render_across_ranks(const MpiJob& job, const TileWork& work, TileSet& set,
                         const std::function<void(const TileSet&)>& after_tile) {
  if (job.rank() != 0) {
    work_for_rank0(job, work);
    return true;
  }
  TileQueue queue(work.grid, set);
  Collector collector(set, after_tile);
  // An exception in either thread (out of memory, a checkpoint that cannot be
  // written, a bad message) stops both; it is rethrown once the second thread
  // has left MPI, so the caller may report it and abort the job.
  std::atomic<bool> failed{false};
  std::exception_ptr server_error, render_error;
  std::thread server([&] {
    try {
      serve_tiles(job, work, queue, collector, failed);
    } catch (...) {
      server_error = std::current_exception();
      failed = true;
    }
  });
  bool finished = true;
  try {
    for (int64_t t; !failed.load() && (t = queue.next()) >= 0;) {
      std::optional<RenderedTile> tile = render_tile(work.render, work.settings, work.grid, uint32_t(t), work.cancel);
      if (!tile) {
        finished = false;
        break;
      }
      collector.add(std::move(tile->pixels), tile->stats);
    }
  } catch (...) {
    render_error = std::current_exception();
    failed = true;
  }
  server.join();
  if (render_error) std::rethrow_exception(render_error);
  if (server_error) std::rethrow_exception(server_error);
  return finished && !(work.cancel && work.cancel->load());
}

}  // namespace pt::dist
