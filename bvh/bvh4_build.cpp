// build_bvh4: input boxes, SAH build, collapse, leaf block fill, statistics.
#include "bvh4_build.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>
#include <string>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "bvh4_collapse.h"
#include "kernels/math/ray.h"
#include "presplit.h"

namespace pt {
namespace {

struct Inputs {
  std::vector<uint32_t> ids;  ///< triangles that enter the BVH
  std::vector<BBox> boxes;
  std::vector<float3> centers;
  float max_abs = 0.0f;
};

/// Exactly zero area: the cross product of the edges, in double (where the
/// products of float differences are exact), vanishes. Such a triangle has
/// nothing to hit, but rounding could make a ray "hit" it at a garbage t.
bool zero_area(const float3& a, const float3& b, const float3& c) {
  double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = double(b[k]) - a[k];
    e2[k] = double(c[k]) - a[k];
  }
  return e1[1] * e2[2] == e1[2] * e2[1] && e1[2] * e2[0] == e1[0] * e2[2] && e1[0] * e2[1] == e1[1] * e2[0];
}

Inputs gather_inputs(std::span<const float3> positions, std::span<const TriangleIndices> triangles) {
  const size_t n = triangles.size();
  std::vector<BBox> boxes(n);
  std::vector<uint8_t> keep(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const TriangleIndices& t = triangles[i];
      const float3 &a = positions[t.v0], &b = positions[t.v1], &c = positions[t.v2];
      keep[i] = is_finite(a) && is_finite(b) && is_finite(c) && !zero_area(a, b, c);
      boxes[i] = BBox::of_point(a);
      boxes[i].expand(b);
      boxes[i].expand(c);
    }
  });
  Inputs in;
  in.ids.reserve(n);
  in.boxes.reserve(n);
  in.centers.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    in.ids.push_back(i);
    in.boxes.push_back(boxes[i]);
    in.centers.push_back(boxes[i].center());
    in.max_abs = std::max({in.max_abs, max_component(abs(boxes[i].lower)), max_component(abs(boxes[i].upper))});
  }
  return in;
}

/// Writes one lane of a block: the triangle's rows v0, e1, e2.
void write_lane(TriangleBlock4& b, int lane, const float3& p0, const float3& p1, const float3& p2) {
  const float3 r1 = p1 - p0, r2 = p2 - p0;
  for (int a = 0; a < 3; ++a) {
    b.v0[a][lane] = p0[a];
    b.r1[a][lane] = r1[a];
    b.r2[a][lane] = r2[a];
  }
}

/// Block lanes name build references; reference r covers kept triangle ref_triangle[r].
void fill_blocks(Bvh4& bvh, const std::vector<uint32_t>& block_prims, const std::vector<uint32_t>& ref_triangle,
                 const Inputs& in, std::span<const float3> positions, std::span<const TriangleIndices> triangles) {
  bvh.blocks.resize(block_prims.size() / 4);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, bvh.blocks.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      TriangleBlock4& b = bvh.blocks[k];
      for (int lane = 0; lane < 4; ++lane) {
        uint32_t p = block_prims[4 * k + lane];
        // Padding lanes repeat lane 0's v0 with zero edges: degenerate, never hit.
        uint32_t id = in.ids[ref_triangle[p != kInvalidId ? p : block_prims[4 * k]]];
        const TriangleIndices& t = triangles[id];
        const float3& p0 = positions[t.v0];
        if (p == kInvalidId) write_lane(b, lane, p0, p0, p0);
        else write_lane(b, lane, p0, positions[t.v1], positions[t.v2]);
        b.prim[lane] = p != kInvalidId ? id : kInvalidId;
      }
    }
  });
}

/// Child references are 32-bit byte offsets: at most 2^32 / 160 leaf blocks
/// (one per reference at worst) and 2^32 / 128 nodes (fewer than references).
constexpr size_t kMaxBvh4References = (size_t(1) << 32) / sizeof(TriangleBlock4) - 1;

}  // namespace

float bvh4_box_padding(float max_abs_coordinate) { return max_abs_coordinate * 0x1p-20f; }

Bvh4 build_bvh4(std::span<const float3> positions, std::span<const TriangleIndices> triangles,
                const Bvh4Options& options, Bvh4BuildStats* stats) {
  auto start = std::chrono::steady_clock::now();
  Bvh4 bvh;
  SahBuildOptions sah = options.sah;
  CollapseCosts collapse = options.collapse;
  sah.max_leaf_size = std::clamp<uint32_t>(sah.max_leaf_size, 1, 4 * bvh4_ref::kMaxLeafBlocks);
  collapse.max_leaf_size = std::clamp<uint32_t>(collapse.max_leaf_size, 1, 4 * bvh4_ref::kMaxLeafBlocks);
  Bvh4Topology topo;
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    Inputs in = gather_inputs(positions, triangles);
    const bool presplit = options.presplit_budget > 0.0f;
    SplitReferences refs;
    if (presplit) {
      std::vector<float3> corners(3 * in.ids.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, in.ids.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const TriangleIndices& t = triangles[in.ids[i]];
          corners[3 * i] = positions[t.v0], corners[3 * i + 1] = positions[t.v1], corners[3 * i + 2] = positions[t.v2];
        }
      });
      refs = presplit_triangles(corners, options.presplit_budget);
    } else {  // one reference per triangle: its box
      refs.boxes = std::move(in.boxes);
      refs.centers = std::move(in.centers);
      refs.triangle.resize(in.ids.size());
      std::iota(refs.triangle.begin(), refs.triangle.end(), 0u);
    }
    if (refs.triangle.size() > kMaxBvh4References)
      throw std::length_error("BVH4: " + std::to_string(refs.triangle.size()) +
                              " build references, more than the 32-bit node and block offsets address");
    if (options.l1_resident_block_cost > 0.0f && refs.triangle.size() <= kL1ResidentTriangles)
      collapse.block = options.l1_resident_block_cost;  // the tree sits in L1 (Bvh4Options)
    Bvh2 bvh2 = build_bvh2_sah(refs.boxes, refs.centers, sah);
    // Only pre-split fragments can repeat a triangle in a leaf.
    std::span<const uint32_t> fragment_key =
        presplit ? std::span<const uint32_t>(refs.triangle) : std::span<const uint32_t>();
    topo = collapse_to_bvh4(bvh2, bvh4_box_padding(in.max_abs), collapse, fragment_key);
    fill_blocks(bvh, topo.block_prims, refs.triangle, in, positions, triangles);
    if (stats) {
      stats->triangles = static_cast<uint32_t>(in.ids.size());
      stats->references = static_cast<uint32_t>(refs.triangle.size());
    }
  });
  bvh.nodes = std::move(topo.nodes);
  bvh.nodes.shrink_to_fit();  // the collapse grew it node by node: keep no slack
  bvh.root = topo.root;
  if (stats) {
    stats->nodes = static_cast<uint32_t>(bvh.nodes.size());
    stats->leaves = topo.leaves;
    stats->blocks = static_cast<uint32_t>(bvh.blocks.size());
    stats->depth = topo.depth;
    stats->sah_cost = topo.sah_cost;
    stats->bytes = bvh.nodes.size() * sizeof(Bvh4Node) + bvh.blocks.size() * sizeof(TriangleBlock4);
    stats->bytes_per_triangle = stats->triangles ? double(stats->bytes) / stats->triangles : 0.0;
    stats->build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  return bvh;
}

}  // namespace pt
