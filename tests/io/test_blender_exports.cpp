// What the loader makes of Blender 3.4's own COLLADA exports (tests/data/
// blender, made by scripts/studies/peers/blender_scenes.sh, whose script states each
// scene's lights, materials and camera): light kinds, Cycles' radiance and
// intensity from the watts, area shapes, smooth and flat normals, diffuse and
// emissive materials, and Blender's camera framing; and the course's older
// files: the CMU462 profile and duplicate node ids.
#include <cmath>
#include <numbers>
#include <string>

#include "io/camera_setup.h"
#include "io/scene_error.h"
#include "support/test_support.h"

namespace pt::blender_exports_test {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

LoadResult load_export(const std::string& name) { return load_collada_file(test::test_data("blender/" + name)); }

void expect_rel(float3 a, float3 b, float rel = 1e-5f) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], rel * std::fabs(b[c]) + 1e-7f) << "channel " << c;
}

/// Blender's Z-up (x, y, z) as the loader's Y-up world.
float3 from_blender(float x, float y, float z) { return {-x, z, y}; }

bool has_warning(const LoadResult& r, const std::string& fragment) {
  for (const std::string& w : r.warnings)
    if (w.find(fragment) != std::string::npos) return true;
  return false;
}

const PointLight* point_at(const Scene& s, float3 p) {
  for (const PointLight& l : s.point_lights)
    if (length(l.position - p) < 1e-4f) return &l;
  return nullptr;
}

TEST(BlenderExports, PointLightsAreWattsOverFourPiWithTheirRadius) {
  LoadResult r = load_export("point_smooth.dae");
  const Scene& s = r.scene;
  ASSERT_EQ(s.point_lights.size(), 2u);
  EXPECT_TRUE(s.area_lights.empty());
  const PointLight* hard = point_at(s, from_blender(1.5f, -2.5f, 3.5f));
  const PointLight* soft = point_at(s, from_blender(-2.5f, -1.0f, 2.5f));
  ASSERT_TRUE(hard && soft);
  EXPECT_EQ(hard->flags, PointLight::kInverseSquare);
  expect_rel(hard->radiance, float3(1.0f, 0.9f, 0.8f) * (800.0f / (4 * kPi)));
  EXPECT_EQ(hard->radius, 0.0f);
  expect_rel(soft->radiance, float3(0.6f, 0.7f, 1.0f) * (300.0f / (4 * kPi)));
  EXPECT_NEAR(soft->radius, 0.3f, 1e-6f);
}

TEST(BlenderExports, SunStrengthIsIrradianceAlongItsNode) {
  LoadResult r = load_export("sun_flat_emissive.dae");
  const Scene& s = r.scene;
  ASSERT_EQ(s.directional_lights.size(), 1u);
  expect_rel(s.directional_lights[0].radiance, float3(2.5f));
  // Euler XYZ (40, 0, 30) degrees applied to +Z.
  const float a = 40 * kPi / 180, b = 30 * kPi / 180;
  float3 expected = from_blender(std::sin(a) * std::sin(b), -std::sin(a) * std::cos(b), std::cos(a));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.directional_lights[0].to_light[c], expected[c], 1e-5f);
  EXPECT_TRUE(has_warning(r, "a sun's angle is not in Blender's export"));
}

TEST(BlenderExports, SpotLightHasItsConeAndBlend) {
  const Scene s = load_export("spot_blend.dae").scene;
  ASSERT_EQ(s.point_lights.size(), 1u);
  const PointLight& l = s.point_lights[0];
  EXPECT_EQ(l.flags, PointLight::kInverseSquare | PointLight::kSpot);
  expect_rel(l.radiance, float3(1500.0f / (4 * kPi)));
  const float tilt = 20 * kPi / 180;  // rotated 20 degrees about X: local -Z -> (0, sin, -cos)
  float3 dir = from_blender(0, std::sin(tilt), -std::cos(tilt));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(l.spot_dir[c], dir[c], 1e-5f);
  EXPECT_NEAR(l.spot_cos_half, std::cos(25 * kPi / 180), 1e-6f);
  EXPECT_NEAR(l.spot_smooth, (1 - std::cos(25 * kPi / 180)) * 0.4f, 1e-6f);
}

TEST(BlenderExports, AreaLightsOfEveryShapeAreWattsOverFourTimesTheirArea) {
  const Scene s = load_export("area_shapes.dae").scene;
  ASSERT_EQ(s.area_lights.size(), 4u);
  struct Expected {
    AreaShape shape;
    float area;
    float3 colour;
  };
  const Expected all[] = {{AreaShape::kParallelogram, 0.36f, {1.0f, 0.5f, 0.5f}},             // square 0.6
                          {AreaShape::kParallelogram, 0.3f, {0.5f, 1.0f, 0.5f}},              // rectangle 1 x 0.3
                          {AreaShape::kEllipse, kPi * 0.16f, {0.5f, 0.5f, 1.0f}},             // disk 0.8
                          {AreaShape::kEllipse, kPi / 4 * 1.2f * 0.4f, {1.0f, 1.0f, 1.0f}}};  // ellipse 1.2 x 0.4
  for (const Expected& e : all) {
    const AreaLight* found = nullptr;
    for (const AreaLight& l : s.area_lights)
      if (l.shape == e.shape && std::fabs(l.area - e.area) < 1e-5f) found = &l;
    ASSERT_TRUE(found) << "area " << e.area;
    expect_rel(found->radiance, e.colour * (150.0f / (4 * e.area)));
  }
  // Triangles: 2 per square and rectangle, kEllipseSegments per disk and ellipse, after the meshes.
  EXPECT_EQ(s.triangles.size() - s.mesh_triangle_count, 2 * 2 + 2 * kEllipseSegments);
}

TEST(BlenderExports, FlatAndSmoothShadingAsExported) {
  const Scene s = load_export("sun_flat_emissive.dae").scene;  // flat cubes and a flat icosphere
  for (uint32_t t = 0; t < s.mesh_triangle_count; ++t) {
    const TriangleIndices& i = s.triangles[t];
    float3 face = normalize(cross(s.positions[i.v1] - s.positions[i.v0], s.positions[i.v2] - s.positions[i.v0]));
    for (uint32_t v : {i.v0, i.v1, i.v2}) ASSERT_GT(std::fabs(dot(s.normals[v], face)), 0.9999f) << "triangle " << t;
  }
  const Scene smooth = load_export("point_smooth.dae").scene;  // a smooth torus and sphere
  size_t curved = 0;
  for (uint32_t t = 0; t < smooth.mesh_triangle_count; ++t) {
    const TriangleIndices& i = smooth.triangles[t];
    if (dot(smooth.normals[i.v0], smooth.normals[i.v1]) < 0.9999f) ++curved;
  }
  EXPECT_GT(curved, 1500u);  // the torus's and the sphere's triangles, not the cube's or the planes'
}

TEST(BlenderExports, MaterialsAreDiffuseColourAndEmission) {
  LoadResult r = load_export("sun_flat_emissive.dae");
  bool red = false, glow = false;
  for (const Material& m : r.scene.materials) {
    red |= m.albedo == float3(0.8f, 0.1f, 0.1f) && !m.is_emitter();
    glow |= m.emission == float3(1.0f, 0.6f, 0.2f) && m.albedo == float3(0.0f);
  }
  EXPECT_TRUE(red);
  EXPECT_TRUE(glow);
  EXPECT_TRUE(has_warning(r, "Blender's exporter drops the emission strength"));
}

TEST(BlenderExports, CameraSitsAtItsNodeWithBlendersFraming) {
  const Scene s = load_export("area_shapes.dae").scene;  // portrait, 35 mm lens on a 24 mm sensor
  ASSERT_TRUE(s.camera.placed);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.camera.position[c], from_blender(0, -4.0f, 1.2f)[c], 1e-5f);
  float3 forward = normalize(from_blender(0, 0.5f, 0) - from_blender(0, -4.0f, 1.2f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(-s.camera.to_camera[c], forward[c], 1e-5f);
  EXPECT_NEAR(s.camera.screen_y.y, std::sqrt(1 - forward.y * forward.y), 1e-5f);  // Blender's +Y is the image's up
  // Auto fit: the sensor width spans the longer side, here the height.
  Camera portrait = resolve_camera(s, 120, 160);
  EXPECT_NEAR(portrait.tan_half_vfov, 12.0f / 35.0f, 1e-5f);
  EXPECT_NEAR(portrait.tan_half_hfov, 12.0f / 35.0f * 0.75f, 1e-5f);
  Camera landscape = resolve_camera(s, 160, 120);
  EXPECT_NEAR(landscape.tan_half_hfov, 12.0f / 35.0f, 1e-5f);
  // Horizontal fit in a landscape image: an 18 mm lens on the 36 mm sensor spans 90 degrees across.
  Camera room = resolve_camera(load_export("room_horizontal_fit.dae").scene, 160, 120);
  EXPECT_NEAR(room.tan_half_hfov, 1.0f, 1e-5f);
  EXPECT_NEAR(room.tan_half_vfov, 0.75f, 1e-5f);
}

TEST(BlenderExports, SceneInfoListsWhatWasLoadedAndIgnored) {
  std::string info = scene_info(load_export("sun_flat_emissive.dae"));
  for (const char* fragment :
       {"read as a Blender 2.80+ export", "node Sun: sun Sun: strength 2.5 W/m^2",
        "node Cube: mesh Cube, 12 triangles, flat", "Glow diffuse (0, 0, 0), emission (1, 0.6, 0.2)",
        "node Camera: camera Camera: at its node", "ignored or changed", "a sun's angle is not in Blender's export"})
    EXPECT_NE(info.find(fragment), std::string::npos) << fragment << "\n" << info;
}

// The same light written by an older Blender (the CS184 files are 2.72 and
// 2.74 exports) keeps the course's reading, and the unread technique is named.
TEST(BlenderExports, OlderBlenderExportsAreReadAsTheCourseReadsThem) {
  std::string text = test::file_bytes(test::test_data("blender/point_smooth.dae"));
  text.replace(text.find("Blender 3.4.1"), 13, "Blender 2.74.0");
  LoadResult r = test::load_string(text, "old.dae");
  ASSERT_EQ(r.scene.point_lights.size(), 2u);
  for (const PointLight& l : r.scene.point_lights) EXPECT_EQ(l.flags, 0u);
  EXPECT_FALSE(r.scene.camera.placed);
  EXPECT_TRUE(has_warning(r, "technique profile \"blender\" is not read"));
  EXPECT_TRUE(has_warning(r, "their colours are read as radiance"));
}

// ------------------------------------------------ the course's older scenes

std::string file(const std::string& libraries, const std::string& nodes) {
  return R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">)"
         "<asset><up_axis>Y_UP</up_axis></asset>" +
         libraries + "<library_visual_scenes><visual_scene id=\"s\">" + nodes +
         "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>";
}

const std::string kCmu462Sphere = R"(<library_effects><effect id="glass-effect"><profile_COMMON><technique sid="c">
  <phong><diffuse><color>1 1 1 1</color></diffuse></phong></technique></profile_COMMON><extra>
  <technique profile="CMU462"><glass><ior>1.5</ior></glass></technique></extra></effect></library_effects>
  <library_materials><material id="glass"><instance_effect url="#glass-effect"/></material></library_materials>
  <library_geometries><geometry id="ball"><extra><technique profile="CMU462"><sphere><radius>0.5</radius></sphere>
  </technique></extra></geometry></library_geometries>
  <library_lights><light id="l"><technique_common><point><color>1 1 1</color></point></technique_common>
  <extra><technique profile="CMU462"><area><color>3 3 3</color></area></technique></extra></light></library_lights>)";

std::string ball(const std::string& id) {
  return "<node id=\"" + id + R"("><instance_geometry url="#ball"><bind_material><technique_common>
    <instance_material symbol="m" target="#glass"/></technique_common></bind_material></instance_geometry></node>)";
}

TEST(CourseScenes, Cmu462ProfileIsReadAsCgl) {
  LoadResult r = test::load_string(file(kCmu462Sphere, ball("a") + "<node><instance_light url=\"#l\"/></node>"));
  ASSERT_EQ(r.scene.spheres.size(), 1u);
  EXPECT_EQ(r.scene.materials[r.scene.spheres[0].material].kind, MaterialKind::kGlass);
  ASSERT_EQ(r.scene.area_lights.size(), 1u);
  EXPECT_EQ(r.scene.area_lights[0].radiance, float3(3.0f));
  EXPECT_TRUE(r.warnings.empty());
}

TEST(CourseScenes, DuplicateNodeIdsThatNothingReferencesLoadWithOneWarning) {
  LoadResult r = test::load_string(file(kCmu462Sphere, ball("Sphere") + ball("Sphere") + ball("Other") + ball("Other") +
                                                           "<node><instance_light url=\"#l\"/></node>"));
  EXPECT_EQ(r.scene.spheres.size(), 4u);  // every node kept, as the course renderer keeps them
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("2 id(s) carried by more than one <node> (\"Other\""), std::string::npos)
      << r.warnings[0];
}

TEST(CourseScenes, ADuplicateNodeIdThatAReferenceNamesIsRefused) {
  std::string lib = kCmu462Sphere + "<library_nodes>" + ball("twin") + ball("twin") + "</library_nodes>";
  try {
    test::load_string(file(lib, "<node><instance_node url=\"#twin\"/></node>"));
    FAIL() << "loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("<instance_node url=\"#twin\">: refers to \"#twin\", which several <node> "
                                         "elements carry"),
              std::string::npos)
        << e.what();
  }
}

TEST(CourseScenes, ADuplicateIdOnAnythingButNodesIsStillRefused) {
  EXPECT_THROW(
      test::load_string(file(kCmu462Sphere + "<library_cameras><camera id=\"ball\"/></library_cameras>", ball("a"))),
      InputError);
}

TEST(Warnings, AllLightsSkippedIsSaidBeforeRendering) {
  std::string lights = R"(<library_lights><light id="spotlight"><technique_common><spot><color>1 1 1</color></spot>
    </technique_common></light></library_lights>)";
  LoadResult r =
      test::load_string(file(kCmu462Sphere + lights, ball("a") + "<node><instance_light url=\"#spotlight\"/></node>"));
  EXPECT_TRUE(has_warning(r, "all 1 lights the scene places were skipped"));
}

TEST(Warnings, TexturesAndSpecularAreNamed) {
  std::string libs = R"(<library_effects><effect id="e"><profile_COMMON><technique sid="c"><phong>
    <diffuse><texture texture="wood" texcoord="UV"/></diffuse><specular><color>0.5 0.5 0.5 1</color></specular>
    </phong></technique></profile_COMMON></effect></library_effects>
    <library_materials><material id="m"><instance_effect url="#e"/></material></library_materials>)";
  std::string node = R"(<node><instance_geometry url="#ball"><bind_material><technique_common>
    <instance_material symbol="m" target="#m"/></technique_common></bind_material></instance_geometry></node>)";
  LoadResult r = test::load_string(file(kCmu462Sphere + libs, node + "<node><instance_light url=\"#l\"/></node>"));
  EXPECT_TRUE(has_warning(r, "<diffuse>: a texture is not modelled"));
  EXPECT_TRUE(has_warning(r, "<specular>: <phong> property not modelled"));
}

}  // namespace
}  // namespace pt::blender_exports_test
