// The plain binary files that let anyone time a tracer on exactly the rays
// another tracer traced (no headers, little-endian):
//   triangles: float32 x, y, z per vertex, 9 floats per triangle (triangle i = primitive i);
//   rays:      float32 ox, oy, oz, tmin, dx, dy, dz, tmax (32 bytes per ray, the Ray layout);
//   hits:      float32 t, uint32 primitive per ray (a miss: t = tmax, 0xFFFFFFFF).
// Readers throw InputError naming the file; writers write whole files or
// none (atomic_file.h).
#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"

namespace pt {

/// A triangle soup as a Scene: vertices 3i, 3i+1, 3i+2 form triangle i.
Scene read_triangle_file(const std::filesystem::path& path);
void write_triangle_file(const std::filesystem::path& path, const Scene& scene);

std::vector<Ray> read_ray_file(const std::filesystem::path& path);
void write_ray_file(const std::filesystem::path& path, std::span<const Ray> rays);

void write_hit_file(const std::filesystem::path& path, const std::vector<Hit>& hits);

}  // namespace pt
