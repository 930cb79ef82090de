// Blocks rewritten for the watertight test (watertight_blocks.h).
#include "watertight_blocks.h"

namespace pt::bench {

Bvh4 to_watertight(const Bvh4& bvh, std::span<const float3> positions, std::span<const TriangleIndices> triangles) {
  Bvh4 out = bvh;
  for (TriangleBlock4& b : out.blocks)
    for (int lane = 0; lane < 4; ++lane) {
      if (b.prim[lane] == kInvalidId) {  // padding: v0 three times, degenerate
        for (int a = 0; a < 3; ++a) b.r1[a][lane] = b.r2[a][lane] = b.v0[a][lane];
        continue;
      }
      const TriangleIndices& t = triangles[b.prim[lane]];
      for (int a = 0; a < 3; ++a) {
        b.v0[a][lane] = positions[t.v0][a];
        b.r1[a][lane] = positions[t.v1][a];
        b.r2[a][lane] = positions[t.v2][a];
      }
    }
  return out;
}

}  // namespace pt::bench
