// Blender's lights as Cycles renders them, end to end: a Blender 3.4 COLLADA
// file (the `blender` technique as Blender's exporter writes it) over a
// Lambertian floor of albedo kRho, loaded and rendered at -m 1 by every
// engine, against the irradiance E that Cycles' conventions give, computed
// here from the file's watts and not by any renderer code (the floor's
// radiance is kRho / pi * E):
//  - point light of power P at height d: E = P / (4 pi d^2) cos;
//  - spot light: the same, times Cycles' spot attenuation (the cosine to the
//    axis inside the cone, times smoothstep over the blend's band of cosines);
//  - sun of strength S: E = S cos;
//  - point light of radius r (Cycles samples a disk facing the point and
//    weighs each sample as I / t^2, its cosine taken as 1), right below it:
//    E = I E[cos / t^2] = I (2 d / r^2) (1 / d - 1 / sqrt(d^2 + r^2));
//  - disk area light of diameter D = 2r, power P (Cycles' radiance
//    L = P / (4 A)), right below it: E = pi L r^2 / (d^2 + r^2);
//  - rectangular area light: E = L x its projected solid angle.
// Delta lights are exact (1e-5; the spot's band 1e-4); the others are estimates over 16 x 16 pixels
// that all see one point (z-test at 5 standard errors: film_checks.h).
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "io/collada_loader.h"
#include "support/engines_under_test.h"
#include "support/film_checks.h"
#include "support/form_factors.h"
#include "support/scene_builders.h"
#include "support/test_support.h"

namespace pt::blender_lights_test {
namespace {

constexpr double kPi = std::numbers::pi;
const float3 kRho{0.8f, 0.5f, 0.3f};

/// A Blender 3.4 export (Z up): a 40 x 40 floor at z = 0 (flat, its normal in
/// the file) and one light node with `matrix` (row-major) and `technique`.
std::string blender_file(const std::string& common, const std::string& technique, const std::string& matrix) {
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><contributor><authoring_tool>Blender 3.4.1</authoring_tool></contributor><up_axis>Z_UP</up_axis></asset>
<library_lights><light id="L-light" name="L"><technique_common>)" +
         common + R"(</technique_common><extra><technique profile="blender">)" + technique +
         R"(</technique></extra></light></library_lights>
<library_effects><effect id="F-effect"><profile_COMMON><technique sid="common"><lambert>
<emission><color sid="emission">0 0 0 1</color></emission><diffuse><color sid="diffuse">0.8 0.5 0.3 1</color></diffuse>
<index_of_refraction><float sid="ior">1.45</float></index_of_refraction></lambert></technique></profile_COMMON></effect>
</library_effects>
<library_materials><material id="F-material" name="Floor"><instance_effect url="#F-effect"/></material></library_materials>
<library_geometries><geometry id="Plane-mesh" name="Plane"><mesh>
<source id="Plane-mesh-positions"><float_array id="pa" count="12">-20 -20 0 20 -20 0 -20 20 0 20 20 0</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
<source id="Plane-mesh-normals"><float_array id="na" count="3">0 0 1</float_array>
<technique_common><accessor source="#na" count="1" stride="3"/></technique_common></source>
<vertices id="Plane-mesh-vertices"><input semantic="POSITION" source="#Plane-mesh-positions"/></vertices>
<triangles material="F-material" count="2"><input semantic="VERTEX" source="#Plane-mesh-vertices" offset="0"/>
<input semantic="NORMAL" source="#Plane-mesh-normals" offset="1"/><p>0 0 1 0 3 0 0 0 3 0 2 0</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="Scene" name="Scene">
<node id="L" name="L" type="NODE"><matrix sid="transform">)" +
         matrix + R"(</matrix><instance_light url="#L-light"/></node>
<node id="Plane" name="Plane" type="NODE"><matrix sid="transform">1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>
<instance_geometry url="#Plane-mesh" name="Plane"><bind_material><technique_common>
<instance_material symbol="F-material" target="#F-material"/></technique_common></bind_material></instance_geometry></node>
</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#Scene"/></scene></COLLADA>)";
}

std::string light_technique(int type, double energy, const std::string& more = "") {
  return "<type sid=\"type\" type=\"int\">" + std::to_string(type) +
         "</type><red>1</red><green>1</green><blue>1</blue>" + "<energy sid=\"blender_energy\" type=\"float\">" +
         std::to_string(energy) + "</energy>" + more;
}

std::string translation(double x, double y, double z) {
  return "1 0 0 " + std::to_string(x) + " 0 1 0 " + std::to_string(y) + " 0 0 1 " + std::to_string(z) + " 0 0 0 1";
}

/// Blender's floor point (x, y) seen from above by a camera that sees nothing else.
Film render_floor_point(const test::EngineUnderTest& e, const Scene& s, double x, double y, RenderSettings rs) {
  // Blender (x, y, z) is (-x, z, y) in the loaded scene (Y up).
  const float3 p{static_cast<float>(-x), 0.0f, static_cast<float>(y)};
  return e.render(s, test::look_at(p + float3{0.03f, 1.0f, 0.02f}, p, 1e-6f, 1e-6f), rs).film;
}

Scene load(const std::string& xml) {
  LoadResult r = test::load_string(xml, "blender.dae");
  return std::move(r.scene);
}

float3 floor_radiance(double irradiance) { return kRho * static_cast<float>(irradiance / kPi); }

// Catches: watts read as radiance (the course's reading), a missing 1 / (4 pi),
// no inverse-square falloff, the cosine at the floor.
TEST(BlenderLights, PointLightIsPowerOverFourPiWithInverseSquareFalloff) {
  const double P = 250.0, h = 2.0;
  Scene s =
      load(blender_file("<point><color>250 250 250</color></point>", light_technique(0, P), translation(0, 0, h)));
  for (double x : {0.0, 0.7, 2.5}) {
    const double d2 = h * h + x * x, cosine = h / std::sqrt(d2);
    for (const test::EngineUnderTest& e : test::engines_under_test())
      test::expect_film_equals(render_floor_point(e, s, x, 0.0, test::fixed_settings(4, 4, 4)),
                               floor_radiance(P / (4 * kPi * d2) * cosine), e.name + ", x " + std::to_string(x), 1e-5);
  }
}

// Catches: the sun's strength taken as anything but irradiance, its direction.
TEST(BlenderLights, SunStrengthIsIrradiance) {
  // Rotated 30 degrees about Blender's X: its light arrives along (0, sin 30, -cos 30).
  const double a = kPi / 6, S = 3.0;
  std::string m = "1 0 0 0 0 " + std::to_string(std::cos(a)) + " " + std::to_string(-std::sin(a)) + " 0 0 " +
                  std::to_string(std::sin(a)) + " " + std::to_string(std::cos(a)) + " 5 0 0 0 1";
  Scene s = load(blender_file("<directional><color>3 3 3</color></directional>", light_technique(1, S), m));
  for (const test::EngineUnderTest& e : test::engines_under_test())
    test::expect_film_equals(render_floor_point(e, s, 0.3, -0.2, test::fixed_settings(4, 4, 4)),
                             floor_radiance(S * std::cos(a)), e.name, 1e-5);
}

// Catches: a spot cone of the wrong angle (Blender writes the whole cone),
// the blend's smooth band, and the cosine to the axis that Cycles 3.4 keeps
// inside the cone.
TEST(BlenderLights, SpotLightHasCyclesConeBlendAndAttenuation) {
  const double P = 400.0, h = 2.0, cone_deg = 60.0, blend = 0.5;
  Scene s = load(blender_file("<spot><color>400 400 400</color></spot>",
                              light_technique(2, P,
                                              "<spotsize>" + std::to_string(cone_deg) + "</spotsize><spotblend>" +
                                                  std::to_string(blend) + "</spotblend><area_size>0</area_size>"),
                              translation(0, 0, h)));
  const double cos_half = std::cos(cone_deg / 2 * kPi / 180), smooth = (1 - cos_half) * blend;
  for (double x : {0.0, 0.9, 1.05, 1.5}) {  // axis, inside the band, at its edge, outside the cone
    const double d2 = h * h + x * x, c = h / std::sqrt(d2), t = c - cos_half;
    double att = 0.0;
    if (t > 0) {
      const double u = std::min(1.0, t / smooth);
      att = c * u * u * (3 - 2 * u);
    }
    for (const test::EngineUnderTest& e : test::engines_under_test())
      // 1e-4: within the band, smoothstep of t = cos - cos_half (a difference of nearby float
      // cosines, t / cos down to 0.02) magnifies their rounding ten-fold.
      test::expect_film_equals(render_floor_point(e, s, x, 0.0, test::fixed_settings(4, 4, 4)),
                               floor_radiance(P / (4 * kPi * d2) * c * att), e.name + ", x " + std::to_string(x), 1e-4);
  }
}

// Catches: a radius ignored (the point light's 1 / d^2), a disk not facing
// the point, or the disk's points weighted by a cosine Cycles does not apply.
TEST(BlenderLights, PointLightWithARadiusIsCyclesSoftDisk) {
  const double P = 300.0, h = 1.0, r = 0.8;
  Scene s = load(blender_file("<point><color>300 300 300</color></point>",
                              light_technique(0, P, "<area_size>" + std::to_string(r) + "</area_size>"),
                              translation(0, 0, h)));
  const double I = P / (4 * kPi);
  const double expected = I * (2 * h / (r * r)) * (1 / h - 1 / std::sqrt(h * h + r * r));
  for (const test::EngineUnderTest& e : test::engines_under_test())
    test::expect_film_estimates(render_floor_point(e, s, 0.0, 0.0, test::fixed_settings(16, 16, 64)),
                                floor_radiance(expected), e.name);
}

// Catches: the area light's radiance other than P / (4 A), a disk taken as its
// square (area 4 / pi times too large), and its sampling.
TEST(BlenderLights, DiskAreaLightIsPowerOverFourTimesItsArea) {
  const double P = 200.0, h = 1.5, D = 1.2, r = D / 2;
  Scene s = load(blender_file("<point><color>200 200 200</color></point>",
                              light_technique(4, P,
                                              "<area_shape>4</area_shape><area_size>" + std::to_string(D) +
                                                  "</area_size><area_sizey>0.25</area_sizey>"),
                              translation(0, 0, h)));
  ASSERT_EQ(s.area_lights.size(), 1u);
  EXPECT_NEAR(s.area_lights[0].area, kPi * r * r, 1e-5);
  const double L = P / (4 * kPi * r * r);
  // Depth 2: under MIS the floor's BSDF ray competes, and finds the disk's fan of triangles.
  for (int m : {1, 2})
    for (const test::EngineUnderTest& e : test::engines_under_test()) {
      RenderSettings rs = test::fixed_settings(16, 16, 64);
      rs.max_depth = m;
      test::expect_film_estimates(render_floor_point(e, s, 0.0, 0.0, rs),
                                  floor_radiance(kPi * L * r * r / (h * h + r * r)),
                                  e.name + ", m " + std::to_string(m));
    }
}

// Catches: sizes swapped between the rectangle's axes, the radiance P / (4 A).
TEST(BlenderLights, RectangularAreaLightIsPowerOverFourTimesItsArea) {
  const double P = 120.0, h = 1.0, sx = 1.0, sy = 0.4;
  Scene s = load(blender_file("<point><color>120 120 120</color></point>",
                              light_technique(4, P,
                                              "<area_shape>1</area_shape><area_size>" + std::to_string(sx) +
                                                  "</area_size><area_sizey>" + std::to_string(sy) + "</area_sizey>"),
                              translation(0, 0, h)));
  const double L = P / (4 * sx * sy), px = 0.6, py = 0.1;  // a floor point off to the side
  const double psa = test::projected_solid_angle(-sx / 2, sx / 2, -sy / 2, sy / 2, h, px, py);
  for (const test::EngineUnderTest& e : test::engines_under_test())
    test::expect_film_estimates(render_floor_point(e, s, px, py, test::fixed_settings(16, 16, 64)),
                                floor_radiance(L * psa), e.name);
}

}  // namespace
}  // namespace pt::blender_lights_test
