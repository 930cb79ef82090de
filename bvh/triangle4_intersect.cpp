// Out-of-line parts of the block tests: the watertight ray setup and the
// double-precision fallback for edge functions that are exactly zero.
#include "kernels/simd/isa_namespace.h"
#include "triangle4_intersect.h"

#include <utility>

namespace pt {
inline namespace PT_ISA_NS {

WatertightBlockRay::WatertightBlockRay(const Ray& r) : tmin(r.tmin) {
  float3 a = abs(r.dir);
  kz = static_cast<uint32_t>(max_axis(a));
  kx = (kz + 1) % 3;
  ky = (kx + 1) % 3;
  if (r.dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding
  sx = vfloat4(r.dir[kx] / r.dir[kz]);
  sy = vfloat4(r.dir[ky] / r.dir[kz]);
  sz = vfloat4(1.0f / r.dir[kz]);
  org[0] = vfloat4(r.org[kx]);
  org[1] = vfloat4(r.org[ky]);
  org[2] = vfloat4(r.org[kz]);
}

void watertight_edges_in_double(const float ax[4], const float ay[4], const float bx[4], const float by[4],
                                const float cx[4], const float cy[4], uint32_t lanes, vfloat4& u, vfloat4& v,
                                vfloat4& w) {
  alignas(16) float fu[4], fv[4], fw[4];
  u.store_aligned(fu);
  v.store_aligned(fv);
  w.store_aligned(fw);
  for (int i = 0; i < 4; ++i) {
    if (!(lanes >> i & 1)) continue;
    fu[i] = static_cast<float>(double(cx[i]) * by[i] - double(cy[i]) * bx[i]);
    fv[i] = static_cast<float>(double(ax[i]) * cy[i] - double(ay[i]) * cx[i]);
    fw[i] = static_cast<float>(double(bx[i]) * ay[i] - double(by[i]) * ax[i]);
  }
  u = vfloat4::load_aligned(fu);
  v = vfloat4::load_aligned(fv);
  w = vfloat4::load_aligned(fw);
}

}  // namespace PT_ISA_NS
}  // namespace pt
