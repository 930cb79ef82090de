// Intel Embree 3 behind the benchmark's tracer interface, with every way it
// traces: single rays (rtcIntersect1 / rtcOccluded1), packets of 4, 8 and 16
// (rtcIntersect4/8/16, rtcOccluded4/8/16), and streams of a whole queue, of
// records (rtcIntersect1M / rtcOccluded1M) and of arrays (rtcIntersectNp /
// rtcOccludedNp); packets and streams with the incoherent or the coherent
// context flag. One
// triangle mesh shares the benchmark's vertex and index arrays, built with a
// chosen quality, on a device restricted to the instruction set this
// renderer's kernels run at (Embree's "isa=" device config). Rays are
// converted to Embree's forms once per ray set, outside the timed loops; the
// timed calls copy them into per-thread records (Embree writes its answers
// into the rays). Benchmark only: the renderer never uses Embree.
#pragma once

#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"
#include "kernels/simd/isa.h"
#include "ray_sets.h"

namespace pt::bench {

enum class EmbreeMethod {
  kSingle,  ///< rtcIntersect1 / rtcOccluded1
  kPacket4,
  kPacket8,
  kPacket16,
  kPacket4Coherent,  ///< the packets with the coherent context flag
  kPacket8Coherent,
  kPacket16Coherent,
  kStream,          ///< rtcIntersect1M / rtcOccluded1M over a queue, incoherent flag
  kStreamCoherent,  ///< the same with the coherent flag
  kArrays,          ///< rtcIntersectNp / rtcOccludedNp over a queue, incoherent flag
  kArraysCoherent,
};
inline constexpr std::array<EmbreeMethod, 11> kEmbreeMethods = {
    EmbreeMethod::kSingle,           EmbreeMethod::kPacket4,         EmbreeMethod::kPacket8,
    EmbreeMethod::kPacket16,         EmbreeMethod::kPacket4Coherent, EmbreeMethod::kPacket8Coherent,
    EmbreeMethod::kPacket16Coherent, EmbreeMethod::kStream,          EmbreeMethod::kStreamCoherent,
    EmbreeMethod::kArrays,           EmbreeMethod::kArraysCoherent};
/// "single", "packet4", ..., "packet16_coherent", "stream", "stream_coherent", "arrays", "arrays_coherent".
const char* embree_method_name(EmbreeMethod m);

/// Embree's forms of one ray set: records, packets of each width built queue
/// by queue (a queue's last packet padded with inactive lanes), and arrays.
struct EmbreeRays {
  std::vector<RTCRayHit> records;
  std::vector<RTCRayHit4> packets4;
  std::vector<RTCRayHit8> packets8;
  std::vector<RTCRayHit16> packets16;
  std::vector<size_t> first_packet[3];  ///< per queue, for widths 4, 8, 16
  std::vector<float> arrays[8];         ///< org x y z, tnear, dir x y z, tfar... see embree_tracer.cpp
  const RaySet* set = nullptr;
};
EmbreeRays convert_rays(const RaySet& set);

class EmbreeTracer {
 public:
  /// Builds over the scene's triangles on all threads of the current TBB arena.
  EmbreeTracer(const Scene& scene, RTCBuildQuality quality);
  ~EmbreeTracer();
  EmbreeTracer(const EmbreeTracer&) = delete;
  EmbreeTracer& operator=(const EmbreeTracer&) = delete;

  /// Traces the queues of the set that lie in rays [begin, end) (begin and
  /// end are queue ends): closest hits into hits[begin, end), or occlusion
  /// into blocked[begin, end).
  void trace(EmbreeMethod method, const EmbreeRays& rays, size_t begin, size_t end, Hit* hits, uint8_t* blocked) const;

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
