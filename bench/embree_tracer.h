// Intel Embree 3 behind the benchmark's tracer interface: a scene of one
// triangle mesh sharing the benchmark's vertex and index arrays, built with
// a chosen quality, on a device restricted to the instruction set this
// renderer's kernels run at (Embree's "isa=" device config); single-ray queries (rtcIntersect1 / rtcOccluded1) and
// packets of 4, 8 or 16 rays (rtcIntersect4/8/16). Rays are converted to
// Embree's records once per ray set, outside the timed loops. Benchmark only:
// the renderer never uses Embree.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/simd/isa.h"
#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"

namespace pt::bench {

/// Embree's records of one ray set: single rays, and packets (padded with
/// invalid lanes) for each packet width.
struct EmbreeRays {
  std::vector<RTCRayHit> single;
  std::vector<RTCRayHit4> packets4;
  std::vector<RTCRayHit8> packets8;
  std::vector<RTCRayHit16> packets16;
  size_t count = 0;
};
EmbreeRays convert_rays(const std::vector<Ray>& rays, bool with_packets);

class EmbreeTracer {
 public:
  /// Builds over the scene's triangles on all threads of the current TBB arena.
  EmbreeTracer(const Scene& scene, RTCBuildQuality quality);
  ~EmbreeTracer();
  EmbreeTracer(const EmbreeTracer&) = delete;
  EmbreeTracer& operator=(const EmbreeTracer&) = delete;

  /// Closest hits of rays [begin, end) into hits[begin, end).
  void intersect1(const EmbreeRays& rays, size_t begin, size_t end, Hit* hits) const;
  /// Packets of `width` (4, 8, 16) consecutive rays; begin and end multiples of width
  /// (end may be the ray count).
  void intersect_packets(const EmbreeRays& rays, int width, size_t begin, size_t end, Hit* hits) const;
  /// Occlusion of rays [begin, end) into blocked[begin, end).
  void occluded1(const EmbreeRays& rays, size_t begin, size_t end, uint8_t* blocked) const;

  double build_ms() const { return build_ms_; }
  /// Bytes Embree holds after the build (memory monitor: allocations minus frees).
  int64_t bytes() const { return bytes_; }

  /// "x.y.z", the instruction set its device is restricted to, and the widest
  /// native packet it reports there.
  static std::string version_and_isa();
  /// Embree's device configuration for the level in use ("isa=avx2").
  static std::string device_config();

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<float> vertices_;  // x, y, z per vertex + one float of padding Embree may read
  double build_ms_ = 0;
  int64_t bytes_ = 0;
};

}  // namespace pt::bench
