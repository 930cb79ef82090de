// --dump-queues: every queue the wavefront traces, collected during a render
// and written afterwards as ray files (io/ray_files.h), one per kind and
// depth, with the scene's triangles: what trace_rays and bench_trace read.
#pragma once

#include <filesystem>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"
#include "wavefront/trace_mode.h"

namespace pt::cli {

class QueueDump {
 public:
  /// The capture hook for WavefrontOptions::capture (any thread).
  wf::QueueCapture hook();
  /// Writes DIR/scene.tris and DIR/<kind>_d<depth>.rays (the queues of a
  /// kind and depth one after the other, in the order they were traced: the
  /// render's order with one thread). Creates DIR; throws InputError if it
  /// cannot write there. Returns the number of rays written.
  size_t write(const std::filesystem::path& dir, const Scene& scene) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<wf::QueueKind, uint32_t>, std::vector<Ray>> queues_;
};

}  // namespace pt::cli
