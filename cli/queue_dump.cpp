// QueueDump: collecting and writing the queues.
#include "queue_dump.h"

#include <string>

#include "io/ray_files.h"
#include "io/scene_error.h"

namespace pt::cli {

wf::QueueCapture QueueDump::hook() {
  return [this](wf::QueueKind kind, uint32_t depth, std::span<const Ray> rays) {
    std::lock_guard lock(mutex_);
    std::vector<Ray>& q = queues_[{kind, depth}];
    q.insert(q.end(), rays.begin(), rays.end());
  };
}

size_t QueueDump::write(const std::filesystem::path& dir, const Scene& scene) const {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw InputError("--dump-queues: cannot create the directory " + dir.string());
  write_triangle_file(dir / "scene.tris", scene);
  std::lock_guard lock(mutex_);
  size_t rays = 0;
  for (const auto& [key, q] : queues_) {
    write_ray_file(dir / (std::string(wf::queue_kind_name(key.first)) + "_d" + std::to_string(key.second) + ".rays"),
                   q);
    rays += q.size();
  }
  return rays;
}

}  // namespace pt::cli
