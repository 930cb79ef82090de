// The scattering math of the non-Lambertian materials, in the local shading
// frame (+z = the shading normal, turned towards the incoming ray, so the
// outgoing direction wo has wo.z > 0), for one float or a SIMD batch: Fresnel
// terms, the smooth dielectric's and the mirror's delta lobes, and the rough
// conductor (Beckmann distribution, Smith shadowing). Every function uses the
// same operations for a float and a batch, so every engine and every
// instruction-set level computes the same bits (lane_math.h's exp and log).
//
// Physically consistent by default; `course` selects the course renderer's
// approximations (--cs184-compat): Schlick's Fresnel for glass, its radiance
// scaling on refraction, its conductor Fresnel evaluated at the macro normal
// with the two-term air-conductor approximation. docs/rendering.md.
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/simd/lane_math.h"
#include "kernels/math/sampling.h"

namespace pt {
inline namespace PT_ISA_NS {

template <class T>
inline Vec3T<T> local_of(const Vec3T<T>& v, const Vec3T<T>& n) {
  Vec3T<T> t, b;
  tangent_frame(n.x, n.y, n.z, t, b);
  return {v.x * t.x + v.y * t.y + v.z * t.z, v.x * b.x + v.y * b.y + v.z * b.z, v.x * n.x + v.y * n.y + v.z * n.z};
}

/// Unpolarised Fresnel reflectance of a smooth dielectric for light arriving
/// at cos_i > 0 onto a medium eta times as dense (eta = eta_t / eta_i); 1
/// under total internal reflection. cos_t receives the transmitted cosine.
template <class T>
inline T fresnel_dielectric(T cos_i, T eta, T& cos_t) {
  T sin2_t = (T(1.0f) - cos_i * cos_i) / (eta * eta);
  cos_t = lane::sqrt(lane::max(T(0.0f), T(1.0f) - sin2_t));
  T rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  T rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return lane::select(sin2_t >= T(1.0f), T(1.0f), T(0.5f) * (rs * rs + rp * rp));
}

/// The course's glass Fresnel: Schlick's approximation with
/// R0 = ((1 - ior) / (1 + ior))^2 at the outgoing cosine.
template <class T>
inline T fresnel_schlick(T cos_o, T ior) {
  T r0 = (T(1.0f) - ior) / (T(1.0f) + ior);
  r0 = r0 * r0;
  T m = T(1.0f) - cos_o;
  T m2 = m * m;
  return r0 + (T(1.0f) - r0) * m2 * m2 * m;
}

/// Fresnel reflectance of a conductor with complex index eta + i k, exact for
/// unpolarised light (pbrt's FrConductor), at cos_i in (0, 1].
template <class T>
inline T fresnel_conductor(T cos_i, T eta, T k) {
  T c2 = cos_i * cos_i, s2 = T(1.0f) - c2;
  T eta2 = eta * eta, k2 = k * k;
  T t0 = eta2 - k2 - s2;
  T a2b2 = lane::sqrt(lane::max(T(0.0f), t0 * t0 + T(4.0f) * eta2 * k2));
  T a = lane::sqrt(lane::max(T(0.0f), T(0.5f) * (a2b2 + t0)));
  T t1 = a2b2 + c2, t2 = T(2.0f) * cos_i * a;
  T rs = (t1 - t2) / (t1 + t2);
  T t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
  T rp = rs * (t3 - t4) / (t3 + t4);
  return T(0.5f) * (rp + rs);
}

/// The course's conductor Fresnel: the common air-conductor approximation
/// averaged over the two polarisations.
template <class T>
inline T fresnel_conductor_course(T cos_i, T eta, T k) {
  T c2 = cos_i * cos_i, ek = eta * eta + k * k, two_eta_c = T(2.0f) * eta * cos_i;
  T rs = (ek - two_eta_c + c2) / (ek + two_eta_c + c2);
  T rp = (ek * c2 - two_eta_c + T(1.0f)) / (ek * c2 + two_eta_c + T(1.0f));
  return T(0.5f) * (rs + rp);
}

// ------------------------------------------------------------ delta lobes

/// A delta lobe's choice: local direction, f cos / pdf per channel (the
/// throughput factor), and the lanes where a direction exists.
template <class T>
struct DeltaScatterT {
  Vec3T<T> wi;
  Vec3T<T> weight;
  lane::mask_t<T> ok;
};

template <class T>
inline Vec3T<T> mirror_direction(const Vec3T<T>& wo) {
  return {lane::neg(wo.x), lane::neg(wo.y), wo.z};
}

/// A smooth dielectric at local wo. `front`: the ray arrived from outside
/// (the side the stored normal faces), so it enters a medium ior times as
/// dense. `reflects`: glass (reflect with the Fresnel probability, always
/// under total internal reflection) rather than refraction only (which
/// returns nothing under total internal reflection). `u` picks the lobe.
template <class T>
inline DeltaScatterT<T> scatter_dielectric(const Vec3T<T>& wo, lane::mask_t<T> front, T ior,
                                           const Vec3T<T>& reflectance, const Vec3T<T>& transmittance, T u,
                                           bool reflects, bool course) {
  const T one(1.0f);
  T cos_o = lane::min(lane::abs(wo.z), one);
  T eta = lane::select(front, ior, one / ior);  // eta_t / eta_i along the path's light flow reversed
  T cos_t;
  T fresnel = fresnel_dielectric(cos_o, eta, cos_t);
  lane::mask_t<T> tir = fresnel >= one;
  if (course) fresnel = lane::select(tir, one, fresnel_schlick(cos_o, ior));
  T inv_eta = one / eta;
  // Radiance across the boundary scales by (eta_i / eta_t)^2 = 1 / eta^2; the
  // course divides by its own eta squared, the inverse (both cancel through
  // any closed object).
  T scale = course ? eta * eta : inv_eta * inv_eta;
  Vec3T<T> refracted{lane::neg(wo.x) * inv_eta, lane::neg(wo.y) * inv_eta, lane::neg(cos_t)};
  DeltaScatterT<T> s;
  if (reflects) {
    lane::mask_t<T> reflect = tir || u < fresnel;
    s.wi = select3(reflect, mirror_direction(wo), refracted);
    s.weight = {lane::select(reflect, reflectance.x, transmittance.x * scale),
                lane::select(reflect, reflectance.y, transmittance.y * scale),
                lane::select(reflect, reflectance.z, transmittance.z * scale)};
    s.ok = (reflect || !tir) && wo.z > T(0.0f);
  } else {
    s.wi = refracted;
    s.weight = {transmittance.x * scale, transmittance.y * scale, transmittance.z * scale};
    s.ok = !tir && wo.z > T(0.0f);
  }
  return s;
}

// --------------------------------------------------- Beckmann microfacets

/// Beckmann normal distribution D(h) at cos(theta_h) = c > 0 and
/// tan^2(theta_h) = tan2: exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4). tan2 is
/// passed in, not derived from c, because 1 - c^2 loses all precision for
/// the near-normal microfacets of a small alpha (error amplified 1/alpha^2).
template <class T>
inline T beckmann_d(T c, T tan2, T alpha) {
  T c2 = c * c, a2 = alpha * alpha;
  return lane::select(c > T(0.0f), lane::exp(lane::neg(tan2 / a2)) / (T(kPi) * a2 * c2 * c2), T(0.0f));
}

/// tan^2 of a unit vector's angle to +z, from its components (exact for
/// vectors near +z, unlike (1 - z^2) / z^2).
template <class T>
inline T tan2_of(const Vec3T<T>& v) {
  return (v.x * v.x + v.y * v.y) / (v.z * v.z);
}

/// Smith's Lambda for the Beckmann distribution at cos(theta) = c > 0, by
/// the rational approximation of Walter et al. (2007) (relative error below
/// 0.35% against the erf form).
template <class T>
inline T beckmann_lambda(T c, T alpha) {
  T tan_t = lane::sqrt(lane::max(T(0.0f), T(1.0f) - c * c)) / c;
  T a = T(1.0f) / (alpha * tan_t);
  T l = (T(1.0f) - T(1.259f) * a + T(0.396f) * a * a) / (T(3.535f) * a + T(2.181f) * a * a);
  return lane::select(a < T(1.6f), l, T(0.0f));
}

/// Smith's shadowing-masking G = 1 / (1 + Lambda(wo) + Lambda(wi)).
template <class T>
inline T smith_g(T cos_o, T cos_i, T alpha) {
  return T(1.0f) / (T(1.0f) + beckmann_lambda(cos_o, alpha) + beckmann_lambda(cos_i, alpha));
}

/// A Beckmann-distributed microfacet normal (all normals, pdf D(h) cos h):
/// tan^2 theta = -alpha^2 log(1 - u1), phi = 2 pi u2.
template <class T>
inline Vec3T<T> sample_beckmann_normal(T u1, T u2, T alpha) {
  T tan2 = lane::neg(alpha * alpha * lane::log(T(1.0f) - u1));
  T c = T(1.0f) / lane::sqrt(T(1.0f) + tan2);
  T s = c * lane::sqrt(tan2);  // sin = cos tan: keeps the tiny angles of a small alpha
  T sp, cp;
  lane::sincos_2pi(u2, sp, cp);
  return {s * cp, s * sp, c};
}

/// Parameters of a rough conductor, per lane.
template <class T>
struct ConductorT {
  T alpha;
  Vec3T<T> eta, k;
};

/// The conductor's Fresnel term per channel at cos_i, by the course's
/// approximation or the exact formula.
template <class T>
inline Vec3T<T> conductor_fresnel(const ConductorT<T>& m, T cos_i, bool course) {
  if (course)
    return {fresnel_conductor_course(cos_i, m.eta.x, m.k.x), fresnel_conductor_course(cos_i, m.eta.y, m.k.y),
            fresnel_conductor_course(cos_i, m.eta.z, m.k.z)};
  return {fresnel_conductor(cos_i, m.eta.x, m.k.x), fresnel_conductor(cos_i, m.eta.y, m.k.y),
          fresnel_conductor(cos_i, m.eta.z, m.k.z)};
}

/// BSDF value f(wo, wi) per channel and the pdf with which
/// sample_microfacet picks wi, for local wo, wi above the surface.
template <class T>
struct MicrofacetEvalT {
  Vec3T<T> f;
  T pdf;
};

template <class T>
inline MicrofacetEvalT<T> eval_microfacet(const ConductorT<T>& m, const Vec3T<T>& wo, const Vec3T<T>& wi, bool course) {
  Vec3T<T> h{wo.x + wi.x, wo.y + wi.y, wo.z + wi.z};
  T len = lane::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
  T inv = T(1.0f) / len;
  h = {h.x * inv, h.y * inv, h.z * inv};
  T o_h = wo.x * h.x + wo.y * h.y + wo.z * h.z;
  lane::mask_t<T> ok = wo.z > T(0.0f) && wi.z > T(0.0f) && len > T(0.0f) && o_h > T(0.0f);
  T d = beckmann_d(h.z, tan2_of(h), m.alpha);
  T scale = d * smith_g(wo.z, wi.z, m.alpha) / (T(4.0f) * wo.z * wi.z);
  Vec3T<T> fr = conductor_fresnel(m, course ? wi.z : o_h, course);
  MicrofacetEvalT<T> e;
  e.f = {lane::select(ok, fr.x * scale, T(0.0f)), lane::select(ok, fr.y * scale, T(0.0f)),
         lane::select(ok, fr.z * scale, T(0.0f))};
  e.pdf = lane::select(ok, d * h.z / (T(4.0f) * o_h), T(0.0f));
  return e;
}

/// A sample of the rough conductor: wi reflected about a Beckmann normal,
/// its pdf (D(h) cos h / (4 |wo.h|)), and f cos / pdf = F G |wo.h| / (wo.z h.z).
template <class T>
struct MicrofacetSampleT {
  Vec3T<T> wi;
  T pdf;
  Vec3T<T> weight;
  lane::mask_t<T> ok;
};

template <class T>
inline MicrofacetSampleT<T> sample_microfacet(const ConductorT<T>& m, const Vec3T<T>& wo, T u1, T u2, bool course) {
  Vec3T<T> h = sample_beckmann_normal(u1, u2, m.alpha);
  T o_h = wo.x * h.x + wo.y * h.y + wo.z * h.z;
  MicrofacetSampleT<T> s;
  s.wi = {T(2.0f) * o_h * h.x - wo.x, T(2.0f) * o_h * h.y - wo.y, T(2.0f) * o_h * h.z - wo.z};
  s.ok = o_h > T(0.0f) && s.wi.z > T(0.0f) && wo.z > T(0.0f);
  s.pdf = beckmann_d(h.z, tan2_of(h), m.alpha) * h.z / (T(4.0f) * o_h);
  T scale = smith_g(wo.z, s.wi.z, m.alpha) * o_h / (wo.z * h.z);
  Vec3T<T> fr = conductor_fresnel(m, course ? s.wi.z : o_h, course);
  s.weight = {fr.x * scale, fr.y * scale, fr.z * scale};
  s.ok = s.ok && s.pdf > T(0.0f);
  return s;
}

}  // namespace PT_ISA_NS
}  // namespace pt
