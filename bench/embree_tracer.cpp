// EmbreeTracer: device, shared buffers, build with a memory monitor, queries.
#include "embree_tracer.h"

#include <atomic>
#include <chrono>
#include <cstring>
#include <stdexcept>

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

template <class Packet, int W>
void fill_packets(const std::vector<Ray>& rays, std::vector<Packet>& out) {
  out.resize((rays.size() + W - 1) / W);
  std::memset(out.data(), 0, out.size() * sizeof(Packet));
  for (size_t i = 0; i < out.size() * W; ++i) {
    Packet& p = out[i / W];
    int k = i % W;
    const Ray& r = rays[std::min(i, rays.size() - 1)];  // tails repeat the last ray
    p.ray.org_x[k] = r.org.x;
    p.ray.org_y[k] = r.org.y;
    p.ray.org_z[k] = r.org.z;
    p.ray.dir_x[k] = r.dir.x;
    p.ray.dir_y[k] = r.dir.y;
    p.ray.dir_z[k] = r.dir.z;
    p.ray.tnear[k] = r.tmin;
    p.ray.tfar[k] = r.tmax;
    p.ray.mask[k] = 0xFFFFFFFFu;
    p.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    p.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  }
}

Hit to_hit(float t, float u, float v, unsigned geom, unsigned prim) {
  return geom == RTC_INVALID_GEOMETRY_ID ? Hit{t, 0.0f, 0.0f, kInvalidId} : Hit{t, u, v, prim};
}

template <class Packet, int W, class Fn>
void trace_packets(const std::vector<Packet>& packets, size_t count, size_t begin, size_t end, Hit* hits, Fn&& call) {
  alignas(64) int valid[W];
  for (size_t first = begin; first < end; first += W) {
    Packet p = packets[first / W];
    for (int k = 0; k < W; ++k) valid[k] = first + k < count ? -1 : 0;
    call(valid, p);
    for (int k = 0; k < W && first + k < end; ++k)
      hits[first + k] = to_hit(p.ray.tfar[k], p.hit.u[k], p.hit.v[k], p.hit.geomID[k], p.hit.primID[k]);
  }
}

}  // namespace

EmbreeRays convert_rays(const std::vector<Ray>& rays, bool with_packets) {
  EmbreeRays out;
  out.count = rays.size();
  out.single.resize(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) fill_ray(out.single[i], rays[i]);
  if (with_packets && !rays.empty()) {
    fill_packets<RTCRayHit4, 4>(rays, out.packets4);
    fill_packets<RTCRayHit8, 8>(rays, out.packets8);
    fill_packets<RTCRayHit16, 16>(rays, out.packets16);
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

void EmbreeTracer::intersect1(const EmbreeRays& rays, size_t begin, size_t end, Hit* hits) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (size_t i = begin; i < end; ++i) {
    RTCRayHit rh = rays.single[i];
    rtcIntersect1(scene_, &ctx, &rh);
    hits[i] = to_hit(rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.geomID, rh.hit.primID);
  }
}

void EmbreeTracer::intersect_packets(const EmbreeRays& rays, int width, size_t begin, size_t end, Hit* hits) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RTCScene s = scene_;
  if (width == 4)
    trace_packets<RTCRayHit4, 4>(rays.packets4, rays.count, begin, end, hits,
                                 [&](const int* v, RTCRayHit4& p) { rtcIntersect4(v, s, &ctx, &p); });
  else if (width == 8)
    trace_packets<RTCRayHit8, 8>(rays.packets8, rays.count, begin, end, hits,
                                 [&](const int* v, RTCRayHit8& p) { rtcIntersect8(v, s, &ctx, &p); });
  else
    trace_packets<RTCRayHit16, 16>(rays.packets16, rays.count, begin, end, hits,
                                   [&](const int* v, RTCRayHit16& p) { rtcIntersect16(v, s, &ctx, &p); });
}

void EmbreeTracer::occluded1(const EmbreeRays& rays, size_t begin, size_t end, uint8_t* blocked) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (size_t i = begin; i < end; ++i) {
    RTCRay r = rays.single[i].ray;
    rtcOccluded1(scene_, &ctx, &r);
    blocked[i] = r.tfar < 0.0f;  // Embree sets tfar = -inf when blocked
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
