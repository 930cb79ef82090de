// An order for tracing a large batch of incoherent rays: rays whose origins
// share a cell of an 8x8x8 grid over the scene and whose directions fall in
// the same cell of an 8x8x8 grid over [-1, 1]^3 (L1-normalised) are traced one
// after the other, so they find each other's nodes and leaves in cache.
// Memory-bound traversals (scenes far larger than the caches) gain most.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/math/bbox.h"
#include "kernels/math/ray.h"

namespace pt::bench {

/// 18-bit sort key: origin cell (Morton order) above direction cell.
uint32_t ray_order_key(const Ray& ray, const BBox& bounds);

/// Indices of `rays` sorted by ray_order_key (stable: equal keys keep their
/// input order). Deterministic; keys are computed in the calling oneTBB arena.
std::vector<uint32_t> coherent_order(std::span<const Ray> rays, const BBox& bounds);

}  // namespace pt::bench
