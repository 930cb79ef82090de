// EmbreeTracer: device, shared buffers, build with a memory monitor, and every
// query method over a set's queues.
#include "embree_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "line_aligned_vector.h"

namespace pt::bench {
namespace {

std::atomic<int64_t> g_embree_bytes{0};

bool count_bytes(void*, ssize_t bytes, bool) {
  g_embree_bytes += bytes;
  return true;
}

void fill_ray(RTCRayHit& r, const Ray& in) {
  std::memset(&r, 0, sizeof r);
  r.ray.org_x = in.org.x;
  r.ray.org_y = in.org.y;
  r.ray.org_z = in.org.z;
  r.ray.dir_x = in.dir.x;
  r.ray.dir_y = in.dir.y;
  r.ray.dir_z = in.dir.z;
  r.ray.tnear = in.tmin;
  r.ray.tfar = in.tmax;
  r.ray.mask = 0xFFFFFFFFu;
  r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/// Packets of W rays over each queue of the set; a queue's last packet repeats
/// its last ray in the lanes past its end (inactive when traced).
template <class Packet, int W>
void fill_packets(const RaySet& set, std::vector<Packet>& out, std::vector<size_t>& first) {
  size_t begin = 0;
  for (size_t end : set.queue_ends) {
    first.push_back(out.size());
    for (size_t p = begin; p < end; p += W) {
      Packet packet;
      std::memset(&packet, 0, sizeof packet);
      for (int k = 0; k < W; ++k) {
        const Ray& r = set.rays[std::min(p + k, end - 1)];
        packet.ray.org_x[k] = r.org.x;
        packet.ray.org_y[k] = r.org.y;
        packet.ray.org_z[k] = r.org.z;
        packet.ray.dir_x[k] = r.dir.x;
        packet.ray.dir_y[k] = r.dir.y;
        packet.ray.dir_z[k] = r.dir.z;
        packet.ray.tnear[k] = r.tmin;
        packet.ray.tfar[k] = r.tmax;
        packet.ray.mask[k] = 0xFFFFFFFFu;
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      out.push_back(packet);
    }
    begin = end;
  }
}

Hit to_hit(float t, float u, float v, unsigned geom, unsigned prim) {
  return geom == RTC_INVALID_GEOMETRY_ID ? Hit{t, 0.0f, 0.0f, kInvalidId} : Hit{t, u, v, prim};
}

/// Per-thread working copies: Embree writes its answers into the rays.
struct Scratch {
  std::vector<RTCRayHit> records;
  LineAlignedVector<float> f[9];                 // org x y z, tnear, dir x y z, tfar; time
  LineAlignedVector<unsigned> mask, id, flags;   // ray
  LineAlignedVector<float> ng[3], u, v;          // hit
  LineAlignedVector<unsigned> prim, geom, inst;  // hit

  RTCRayHitNp arrays(const EmbreeRays& rays, size_t b, size_t n) {
    for (int k = 0; k < 8; ++k) f[k].assign(rays.arrays[k].begin() + b, rays.arrays[k].begin() + b + n);
    f[8].assign(n, 0.0f);
    mask.assign(n, 0xFFFFFFFFu);
    id.assign(n, 0);
    flags.assign(n, 0);
    for (auto& a : ng) a.resize(n);
    u.resize(n), v.resize(n), prim.resize(n);
    geom.assign(n, RTC_INVALID_GEOMETRY_ID);
    inst.assign(n, RTC_INVALID_GEOMETRY_ID);
    RTCRayHitNp r{};
    r.ray = {f[0].data(), f[1].data(), f[2].data(), f[3].data(), f[4].data(), f[5].data(),
             f[6].data(), f[8].data(), f[7].data(), mask.data(), id.data(),   flags.data()};
    r.hit.Ng_x = ng[0].data(), r.hit.Ng_y = ng[1].data(), r.hit.Ng_z = ng[2].data();
    r.hit.u = u.data(), r.hit.v = v.data(), r.hit.primID = prim.data(), r.hit.geomID = geom.data();
    r.hit.instID[0] = inst.data();
    return r;
  }
};
thread_local Scratch t_scratch;

template <class Packet, int W, class Fn>
void trace_packets(const std::vector<Packet>& packets, size_t first, size_t b, size_t e, bool occlusion, Hit* hits,
                   uint8_t* blocked, Fn&& call) {
  alignas(64) int valid[W];
  for (size_t p = b, k = first; p < e; p += W, ++k) {
    Packet packet = packets[k];
    for (int l = 0; l < W; ++l) valid[l] = p + l < e ? -1 : 0;
    call(valid, packet);
    for (int l = 0; l < W && p + l < e; ++l) {
      if (occlusion) blocked[p + l] = packet.ray.tfar[l] < 0.0f;  // Embree sets tfar = -inf when blocked
      else
        hits[p + l] =
            to_hit(packet.ray.tfar[l], packet.hit.u[l], packet.hit.v[l], packet.hit.geomID[l], packet.hit.primID[l]);
    }
  }
}

}  // namespace

const char* embree_method_name(EmbreeMethod m) {
  switch (m) {
    case EmbreeMethod::kSingle: return "single";
    case EmbreeMethod::kPacket4: return "packet4";
    case EmbreeMethod::kPacket8: return "packet8";
    case EmbreeMethod::kPacket16: return "packet16";
    case EmbreeMethod::kPacket4Coherent: return "packet4_coherent";
    case EmbreeMethod::kPacket8Coherent: return "packet8_coherent";
    case EmbreeMethod::kPacket16Coherent: return "packet16_coherent";
    case EmbreeMethod::kStream: return "stream";
    case EmbreeMethod::kStreamCoherent: return "stream_coherent";
    case EmbreeMethod::kArrays: return "arrays";
    case EmbreeMethod::kArraysCoherent: return "arrays_coherent";
  }
  return "?";
}

EmbreeRays convert_rays(const RaySet& set) {
  EmbreeRays out;
  out.set = &set;
  out.records.resize(set.rays.size());
  for (size_t i = 0; i < set.rays.size(); ++i) fill_ray(out.records[i], set.rays[i]);
  fill_packets<RTCRayHit4, 4>(set, out.packets4, out.first_packet[0]);
  fill_packets<RTCRayHit8, 8>(set, out.packets8, out.first_packet[1]);
  fill_packets<RTCRayHit16, 16>(set, out.packets16, out.first_packet[2]);
  for (std::vector<float>& a : out.arrays) a.resize(set.rays.size());
  for (size_t i = 0; i < set.rays.size(); ++i) {
    const Ray& r = set.rays[i];
    const float f[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
    for (int k = 0; k < 8; ++k) out.arrays[k][i] = f[k];
  }
  return out;
}

EmbreeTracer::EmbreeTracer(const Scene& scene, RTCBuildQuality quality) {
  device_ = rtcNewDevice(device_config().c_str());
  if (!device_) throw std::runtime_error("rtcNewDevice failed");
  rtcSetDeviceMemoryMonitorFunction(device_, count_bytes, nullptr);
  vertices_.reserve(scene.positions.size() * 3 + 1);
  for (const float3& p : scene.positions) vertices_.insert(vertices_.end(), {p.x, p.y, p.z});
  vertices_.push_back(0.0f);
  int64_t before = g_embree_bytes.load();
  auto start = std::chrono::steady_clock::now();
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, quality);
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geom, quality);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(), 0, 3 * sizeof(float),
                             scene.positions.size());
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, scene.triangles.data(), 0,
                             sizeof(TriangleIndices), scene.triangles.size());
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene_);
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  bytes_ = g_embree_bytes.load() - before;
}

EmbreeTracer::~EmbreeTracer() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeTracer::trace(EmbreeMethod method, const EmbreeRays& rays, size_t begin, size_t end, Hit* hits,
                         uint8_t* blocked) const {
  const RaySet& set = *rays.set;
  const bool occlusion = set.occlusion;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  if (method == EmbreeMethod::kStreamCoherent || method == EmbreeMethod::kArraysCoherent ||
      method == EmbreeMethod::kPacket4Coherent || method == EmbreeMethod::kPacket8Coherent ||
      method == EmbreeMethod::kPacket16Coherent)
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RTCScene s = scene_;
  size_t q = std::upper_bound(set.queue_ends.begin(), set.queue_ends.end(), begin) - set.queue_ends.begin();
  for (size_t b = begin; b < end; ++q) {
    const size_t e = set.queue_ends[q];
    switch (method) {
      case EmbreeMethod::kSingle:
        for (size_t i = b; i < e; ++i) {
          RTCRayHit rh = rays.records[i];
          if (occlusion) {
            rtcOccluded1(s, &ctx, &rh.ray);
            blocked[i] = rh.ray.tfar < 0.0f;
          } else {
            rtcIntersect1(s, &ctx, &rh);
            hits[i] = to_hit(rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.geomID, rh.hit.primID);
          }
        }
        break;
      case EmbreeMethod::kPacket4:
      case EmbreeMethod::kPacket4Coherent:
        trace_packets<RTCRayHit4, 4>(rays.packets4, rays.first_packet[0][q], b, e, occlusion, hits, blocked,
                                     [&](const int* v, RTCRayHit4& p) {
                                       if (occlusion) rtcOccluded4(v, s, &ctx, &p.ray);
                                       else rtcIntersect4(v, s, &ctx, &p);
                                     });
        break;
      case EmbreeMethod::kPacket8:
      case EmbreeMethod::kPacket8Coherent:
        trace_packets<RTCRayHit8, 8>(rays.packets8, rays.first_packet[1][q], b, e, occlusion, hits, blocked,
                                     [&](const int* v, RTCRayHit8& p) {
                                       if (occlusion) rtcOccluded8(v, s, &ctx, &p.ray);
                                       else rtcIntersect8(v, s, &ctx, &p);
                                     });
        break;
      case EmbreeMethod::kPacket16:
      case EmbreeMethod::kPacket16Coherent:
        trace_packets<RTCRayHit16, 16>(rays.packets16, rays.first_packet[2][q], b, e, occlusion, hits, blocked,
                                       [&](const int* v, RTCRayHit16& p) {
                                         if (occlusion) rtcOccluded16(v, s, &ctx, &p.ray);
                                         else rtcIntersect16(v, s, &ctx, &p);
                                       });
        break;
      case EmbreeMethod::kStream:
      case EmbreeMethod::kStreamCoherent: {
        std::vector<RTCRayHit>& r = t_scratch.records;
        r.assign(rays.records.begin() + b, rays.records.begin() + e);
        const unsigned n = static_cast<unsigned>(e - b);
        if (occlusion) {
          rtcOccluded1M(s, &ctx, &r[0].ray, n, sizeof(RTCRayHit));
          for (size_t i = b; i < e; ++i) blocked[i] = r[i - b].ray.tfar < 0.0f;
        } else {
          rtcIntersect1M(s, &ctx, r.data(), n, sizeof(RTCRayHit));
          for (size_t i = b; i < e; ++i) {
            const RTCRayHit& h = r[i - b];
            hits[i] = to_hit(h.ray.tfar, h.hit.u, h.hit.v, h.hit.geomID, h.hit.primID);
          }
        }
        break;
      }
      case EmbreeMethod::kArrays:
      case EmbreeMethod::kArraysCoherent: {
        const unsigned n = static_cast<unsigned>(e - b);
        const RTCRayHitNp rh = t_scratch.arrays(rays, b, n);
        if (occlusion) {
          rtcOccludedNp(s, &ctx, &rh.ray, n);
          for (size_t i = b; i < e; ++i) blocked[i] = rh.ray.tfar[i - b] < 0.0f;
        } else {
          rtcIntersectNp(s, &ctx, &rh, n);
          for (size_t i = b; i < e; ++i)
            hits[i] = to_hit(rh.ray.tfar[i - b], rh.hit.u[i - b], rh.hit.v[i - b], rh.hit.geomID[i - b],
                             rh.hit.primID[i - b]);
        }
        break;
      }
    }
    b = e;
  }
}

std::string EmbreeTracer::device_config() { return "isa=" + std::string(isa_name(active_isa())); }

std::string EmbreeTracer::version_and_isa() {
  RTCDevice d = rtcNewDevice(device_config().c_str());
  std::string v = std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) + "." +
                  std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
                  std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION_PATCH));
  const char* widest = rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)  ? "16 (AVX-512)"
                       : rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) ? "8 (AVX/AVX2)"
                                                                                            : "4 (SSE)";
  rtcReleaseDevice(d);
  return v + ", " + device_config() + ", native packets of " + widest;
}

}  // namespace pt::bench
