// Loader tests: the public scenes' counts, lights and bounds (bounds computed
// independently from the files), the up-axis and transform rules on small
// hand-written files, and malformed files that must fail with one line naming
// the file and the element.
#include <cmath>
#include <fstream>

#include "io/scene_error.h"
#include "support/test_support.h"

namespace pt {
namespace {

using test::load_string;

// ---------------------------------------------------------------- shared scenes

struct SharedSceneExpectation {
  const char* file;
  uint32_t mesh_triangles, light_triangles, spheres;
  size_t area, point, directional;
  bool sky;
  float3 lower, upper;
};

const SharedSceneExpectation kShared[] = {
    {"CBspheres_lambertian.dae", 10, 2, 2, 1, 0, 0, false, {-1, 0, -1}, {1, 1.5f, 1}},
    {"CBempty.dae", 10, 0, 0, 0, 1, 0, false, {-1, 0, -1}, {1, 1.5f, 1}},
    {"CBgems.dae", 250, 2, 0, 1, 0, 0, false, {-1, 0, -1}, {1, 1.5f, 1}},
    {"CBcoil.dae", 7882, 2, 0, 1, 0, 0, false, {-1, 0, -1}, {1, 1.5f, 1}},
    {"CBbunny.dae", 28586, 2, 0, 1, 0, 0, false, {-1, 0, -1}, {1, 1.5f, 1}},
    {"bunny.dae", 33696, 0, 0, 0, 0, 0, true, {-0.75f, -0.0996877f, -0.75f}, {0.75f, 0.864559f, 0.75f}},
    {"cow.dae", 5856, 0, 0, 0, 0, 1, false, {-0.40649f, -0.768043f, -0.833368f}, {0.40649f, 0.68915f, 0.647513f}},
    {"beetle.dae", 7558, 0, 0, 0, 0, 1, false, {-0.336252f, -0.285757f, -0.829615f}, {0.336252f, 0.285757f, 0.829615f}},
    {"teapot.dae", 2464, 0, 0, 0, 0, 1, false, {-0.792625f, -0.388322f, -0.493109f}, {0.792625f, 0.388322f, 0.493109f}},
    {"banana.dae", 2458, 0, 0, 0, 0, 1, true, {-1, 0, -1}, {1, 0.581482f, 1}},
};

class SharedSceneTest : public ::testing::TestWithParam<SharedSceneExpectation> {};

TEST_P(SharedSceneTest, CountsLightsAndBounds) {
  PT_REQUIRE_SHARED_SCENES();
  const SharedSceneExpectation& e = GetParam();
  LoadResult r = load_collada_file(test::shared_scene(e.file));
  const Scene& s = r.scene;
  EXPECT_EQ(s.mesh_triangle_count, e.mesh_triangles);
  EXPECT_EQ(s.triangles.size() - s.mesh_triangle_count, e.light_triangles);
  EXPECT_EQ(s.spheres.size(), e.spheres);
  EXPECT_EQ(s.area_lights.size(), e.area);
  EXPECT_EQ(s.point_lights.size(), e.point);
  EXPECT_EQ(s.directional_lights.size(), e.directional);
  EXPECT_EQ(s.sky.has_value(), e.sky);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(s.bounds.lower[a], e.lower[a], 1e-5f) << "axis " << a;
    EXPECT_NEAR(s.bounds.upper[a], e.upper[a], 1e-5f) << "axis " << a;
  }
  ASSERT_EQ(s.normals.size(), s.positions.size());
  for (const float3& n : s.normals) ASSERT_NEAR(length(n), 1.0f, 1e-5f);
  for (uint32_t m : s.triangle_material) ASSERT_LT(m, s.materials.size());
}

INSTANTIATE_TEST_SUITE_P(Public, SharedSceneTest, ::testing::ValuesIn(kShared), [](const auto& info) {
  std::string n = info.param.file;
  return n.substr(0, n.find('.'));
});

TEST(SharedScenes, CornellAreaLightIsTheCourseLight) {
  PT_REQUIRE_SHARED_SCENES();
  const Scene s = load_collada_file(test::shared_scene("CBbunny.dae")).scene;
  ASSERT_EQ(s.area_lights.size(), 1u);
  const AreaLight& l = s.area_lights[0];
  // Z-up node matrix: scale 0.6 x 0.8 at z = 1.49, facing -Z; in Y-up it hangs at y = 1.49 facing down.
  EXPECT_NEAR(l.position.y, 1.49f, 1e-6f);
  EXPECT_NEAR(l.area, 0.48f, 1e-6f);
  EXPECT_NEAR(l.direction.y, -1.0f, 1e-6f);
  EXPECT_EQ(l.radiance, float3(10.0f));
}

TEST(SharedScenes, GemsCameraMatrixWithFifteenNumbersLoadsWithAWarning) {
  PT_REQUIRE_SHARED_SCENES();
  LoadResult r = load_collada_file(test::shared_scene("CBgems.dae"));
  bool warned = false;
  for (const std::string& w : r.warnings) warned |= w.find("15 numbers") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_NEAR(r.scene.camera.view_dir.z, 1.0f, 1e-6f);  // the usual front view
}

// ---------------------------------------------------------- hand-written files

/// A COLLADA document with the given up axis, library contents and nodes.
std::string collada(const std::string& up, const std::string& libraries, const std::string& nodes) {
  return R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">)"
         "<asset><up_axis>" +
         up + "</up_axis></asset>" + libraries + "<library_visual_scenes><visual_scene id=\"s\">" + nodes +
         "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>";
}

/// One triangle (0,0,0) (1,0,0) (0,1,0) as geometry "tri".
const std::string kTriangleGeometry =
    R"(<library_geometries><geometry id="tri"><mesh>
       <source id="tri-pos"><float_array id="tri-arr" count="9">0 0 0 1 0 0 0 1 0</float_array>
       <technique_common><accessor source="#tri-arr" count="3" stride="3"/></technique_common></source>
       <vertices id="tri-v"><input semantic="POSITION" source="#tri-pos"/></vertices>
       <triangles count="1"><input semantic="VERTEX" source="#tri-v" offset="0"/><p>0 1 2</p></triangles>
       </mesh></geometry></library_geometries>)";

const std::string kTriangleNode = R"(<node id="n"><instance_geometry url="#tri"/></node>)";

void expect_near(float3 a, float3 b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(UpAxis, YUpIsUsedAsIs) {
  Scene s = load_string(collada("Y_UP", kTriangleGeometry, kTriangleNode)).scene;
  expect_near(s.positions[1], {1, 0, 0});
  expect_near(s.positions[2], {0, 1, 0});
}

TEST(UpAxis, ZUpSwapsYAndZAndNegatesX) {
  Scene s = load_string(collada("Z_UP", kTriangleGeometry, kTriangleNode)).scene;
  expect_near(s.positions[1], {-1, 0, 0});  // (1,0,0) -> (-1,0,0)
  expect_near(s.positions[2], {0, 0, 1});   // (0,1,0) -> (0,0,1)
}

TEST(UpAxis, XUpSwapsXAndYAndNegatesZ) {
  Scene s = load_string(collada("X_UP", kTriangleGeometry, kTriangleNode)).scene;
  expect_near(s.positions[1], {0, 1, 0});
  expect_near(s.positions[2], {1, 0, 0});
}

TEST(Transforms, ComposeInDeclarationOrderWithTheParentOnTheLeft) {
  // Parent translates by (10, 0, 0); child scales x by 2 then rotates 90 degrees about z.
  // Child local: p' = S * R * p, so (1,0,0) -> R -> (0,1,0) -> S -> (0,1,0); (0,1,0) -> (-1,0,0) -> (-2,0,0).
  std::string nodes = R"(<node id="parent"><translate>10 0 0</translate>
      <node id="child"><scale>2 1 1</scale><rotate>0 0 1 90</rotate><instance_geometry url="#tri"/></node></node>)";
  Scene s = load_string(collada("Y_UP", kTriangleGeometry, nodes)).scene;
  expect_near(s.positions[0], {10, 0, 0}, 1e-5f);
  expect_near(s.positions[1], {10, 1, 0}, 1e-5f);
  expect_near(s.positions[2], {8, 0, 0}, 1e-5f);
}

TEST(Transforms, MatrixIsRowMajor) {
  std::string nodes = R"(<node id="m"><matrix>1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1</matrix>
      <instance_geometry url="#tri"/></node>)";
  Scene s = load_string(collada("Y_UP", kTriangleGeometry, nodes)).scene;
  expect_near(s.positions[0], {5, 6, 7});
}

TEST(Transforms, InstanceNodeReusesANodeTree) {
  std::string libs = kTriangleGeometry +
                     R"(<library_nodes><node id="shared"><translate>0 0 3</translate>
                        <instance_geometry url="#tri"/></node></library_nodes>)";
  std::string nodes = R"(<node id="a"><translate>1 0 0</translate><instance_node url="#shared"/></node>
                         <node id="b"><translate>2 0 0</translate><instance_node url="#shared"/></node>)";
  Scene s = load_string(collada("Y_UP", libs, nodes)).scene;
  ASSERT_EQ(s.triangles.size(), 2u);
  expect_near(s.positions[0], {1, 0, 3});
  expect_near(s.positions[3], {2, 0, 3});
}

TEST(Meshes, PolylistIsFanTriangulatedUsingTheVertexOffset) {
  // A quad and a triangle; interleaved NORMAL indices (offset 0) and VERTEX indices (offset 1).
  std::string geom = R"(<library_geometries><geometry id="g"><mesh>
     <source id="p"><float_array id="pa" count="15">0 0 0  1 0 0  1 1 0  0 1 0  2 2 0</float_array>
     <technique_common><accessor source="#pa" count="5" stride="3"/></technique_common></source>
     <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
     <polylist count="2"><input semantic="NORMAL" source="#n" offset="0"/>
       <input semantic="VERTEX" source="#v" offset="1"/>
       <vcount>4 3</vcount><p>9 0 9 1 9 2 9 3  9 2 9 4 9 3</p></polylist>
     </mesh></geometry></library_geometries>)";
  Scene s = load_string(collada("Y_UP", geom, R"(<node><instance_geometry url="#g"/></node>)")).scene;
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.triangles[0].v0, 0u);
  EXPECT_EQ(s.triangles[0].v1, 1u);
  EXPECT_EQ(s.triangles[0].v2, 2u);
  EXPECT_EQ(s.triangles[1].v0, 0u);
  EXPECT_EQ(s.triangles[1].v1, 2u);
  EXPECT_EQ(s.triangles[1].v2, 3u);
  EXPECT_EQ(s.triangles[2].v0, 2u);
  EXPECT_EQ(s.triangles[2].v1, 4u);
  EXPECT_EQ(s.triangles[2].v2, 3u);
}

TEST(Meshes, SmoothNormalsAreAreaWeightedOverSharedVertices) {
  // Two triangles share the edge (0,0,0)-(1,0,0): one in the z=0 plane with
  // area 0.5, one in the y=0 plane with area 1.
  std::string geom = R"(<library_geometries><geometry id="g"><mesh>
     <source id="p"><float_array id="pa" count="12">0 0 0  1 0 0  0 1 0  0 0 2</float_array>
     <technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
     <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
     <triangles count="2"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2  0 3 1</p></triangles>
     </mesh></geometry></library_geometries>)";
  Scene s = load_string(collada("Y_UP", geom, R"(<node><instance_geometry url="#g"/></node>)")).scene;
  // Face normals (cross products): (0,0,1) and (0,2,0). Vertex 0: normalise((0,2,1)).
  float inv = 1.0f / std::sqrt(5.0f);
  expect_near(s.normals[0], {0, 2 * inv, inv});
  expect_near(s.normals[2], {0, 0, 1});
  expect_near(s.normals[3], {0, 1, 0});
}

TEST(Spheres, CentreAndRadiusFollowTheNodeTransform) {
  std::string geom = R"(<library_geometries><geometry id="sph"><extra><technique profile="CGL">
     <sphere><radius>0.5</radius></sphere></technique></extra></geometry></library_geometries>)";
  std::string nodes = R"(<node><translate>1 2 3</translate><scale>3 3 3</scale>
     <instance_geometry url="#sph"/></node>)";
  Scene s = load_string(collada("Y_UP", geom, nodes)).scene;
  ASSERT_EQ(s.spheres.size(), 1u);
  expect_near(s.spheres[0].center, {1, 2, 3});
  EXPECT_NEAR(s.spheres[0].radius, 1.5f, 1e-6f);
}

const std::string kLights = R"(<library_lights>
   <light id="area"><technique_common><point><color>1 1 1</color></point></technique_common>
     <extra><technique profile="CGL"><area><color>4 5 6</color></area></technique></extra></light>
   <light id="pt"><technique_common><point><color>2 2 2</color></point></technique_common></light>
   <light id="dir"><technique_common><directional><color>3 3 3</color></directional></technique_common></light>
   <light id="sky"><technique_common><ambient><color>0.5 0.5 0.5</color></ambient></technique_common></light>
   <light id="spot"><technique_common><spot><color>1 1 1</color></spot></technique_common></light>
 </library_lights>)";

TEST(Lights, AreaLightIsAUnitSquareScaledByTheNode) {
  // Scale x by 2 and y by 3, rotate so that local -Z points down (-Y), place at (0, 5, 0).
  std::string nodes = R"(<node><translate>0 5 0</translate><rotate>1 0 0 -90</rotate><scale>2 3 1</scale>
     <instance_light url="#area"/></node>)";
  Scene s = load_string(collada("Y_UP", kLights, nodes)).scene;
  ASSERT_EQ(s.area_lights.size(), 1u);
  const AreaLight& l = s.area_lights[0];
  expect_near(l.position, {0, 5, 0}, 1e-5f);
  expect_near(l.direction, {0, -1, 0}, 1e-5f);
  EXPECT_NEAR(l.area, 6.0f, 1e-5f);
  EXPECT_EQ(l.radiance, float3(4, 5, 6));
  // Its two triangles are visible geometry facing the emitting direction.
  ASSERT_EQ(s.triangles.size(), 2u);
  for (const TriangleIndices& t : s.triangles) {
    float3 n = cross(s.positions[t.v1] - s.positions[t.v0], s.positions[t.v2] - s.positions[t.v0]);
    EXPECT_GT(dot(n, l.direction), 0.0f);
  }
  const Material& m = s.materials[s.triangle_material[0]];
  EXPECT_EQ(m.emission, float3(4, 5, 6));
  EXPECT_EQ(m.area_light, 0);
}

TEST(Lights, PointDirectionalAmbientAndSpot) {
  std::string nodes = R"(<node><translate>1 2 3</translate><instance_light url="#pt"/></node>
     <node><rotate>1 0 0 90</rotate><instance_light url="#dir"/></node>
     <node><instance_light url="#sky"/></node><node><instance_light url="#sky"/></node>
     <node><instance_light url="#spot"/></node>)";
  LoadResult r = load_string(collada("Y_UP", kLights, nodes));
  const Scene& s = r.scene;
  ASSERT_EQ(s.point_lights.size(), 1u);
  expect_near(s.point_lights[0].position, {1, 2, 3});
  ASSERT_EQ(s.directional_lights.size(), 1u);
  // Light travels along local -Z rotated 90 degrees about x: -Z -> +Y... so it comes from -Y.
  expect_near(s.directional_lights[0].to_light, {0, -1, 0}, 1e-6f);
  ASSERT_TRUE(s.sky.has_value());
  EXPECT_EQ(s.sky->radiance, float3(1.0f));  // two ambient lights add
  bool spot_warned = false;
  for (const std::string& w : r.warnings) spot_warned |= w.find("spot") != std::string::npos;
  EXPECT_TRUE(spot_warned);
}

TEST(Materials, DiffuseColourEmissionAndCglMirror) {
  std::string libs = kTriangleGeometry + R"(<library_effects>
     <effect id="red"><profile_COMMON><technique><phong><diffuse><color>0.6 0.1 0.1 1</color></diffuse></phong>
       </technique></profile_COMMON></effect>
     <effect id="glow"><profile_COMMON><technique><phong><diffuse><color>0.8 0.8 0.8 1</color></diffuse></phong>
       </technique></profile_COMMON><extra><technique profile="CGL"><emission><radiance>7 8 9</radiance>
       </emission></technique></extra></effect>
     <effect id="mirror"><profile_COMMON><technique><lambert><diffuse><color>0.3 0.3 0.3 1</color></diffuse>
       </lambert></technique></profile_COMMON><extra><technique profile="CGL"><mirror><reflectance>1 1 1
       </reflectance></mirror></technique></extra></effect></library_effects>
     <library_materials><material id="m-red"><instance_effect url="#red"/></material>
       <material id="m-glow"><instance_effect url="#glow"/></material>
       <material id="m-mirror"><instance_effect url="#mirror"/></material></library_materials>)";
  auto bound = [](const char* target) {
    return std::string(R"(<node><instance_geometry url="#tri"><bind_material><technique_common>
        <instance_material symbol="x" target="#)") +
           target + R"("/></technique_common></bind_material>
        </instance_geometry></node>)";
  };
  LoadResult r = load_string(collada(
      "Y_UP", libs,
      bound("m-red") + bound("m-glow") + bound("m-mirror") + R"(<node><instance_geometry url="#tri"/></node>)"));
  const Scene& s = r.scene;
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.materials[s.triangle_material[0]].albedo, float3(0.6f, 0.1f, 0.1f));
  EXPECT_EQ(s.materials[s.triangle_material[1]].emission, float3(7, 8, 9));
  EXPECT_EQ(s.materials[s.triangle_material[1]].albedo, float3(0.0f));
  EXPECT_EQ(s.materials[s.triangle_material[3]].albedo, float3(0.5f));  // unbound: 0.5 grey
  EXPECT_EQ(s.materials[s.triangle_material[2]].kind, MaterialKind::kMirror);
  EXPECT_EQ(s.materials[s.triangle_material[2]].albedo, float3(1.0f));  // the mirror's reflectance
  EXPECT_TRUE(r.warnings.empty());
}

TEST(SharedScenes, NonDiffuseMaterialsAreReadAsTheFileStates) {
  PT_REQUIRE_SHARED_SCENES();
  auto kinds = [](const Scene& s, MaterialKind k) {
    std::vector<const Material*> out;
    for (const Material& m : s.materials)
      if (m.kind == k) out.push_back(&m);
    return out;
  };
  Scene gems = load_collada_file(test::shared_scene("CBgems.dae")).scene;
  auto glass = kinds(gems, MaterialKind::kGlass);
  ASSERT_EQ(glass.size(), 3u);
  for (const Material* m : glass) {
    EXPECT_EQ(m->ior, 1.45f);
    EXPECT_EQ(m->albedo, float3(1.0f));
  }
  EXPECT_EQ(glass[0]->transmittance, float3(1.0f, 0.75f, 0.75f));
  Scene coil = load_collada_file(test::shared_scene("CBcoil.dae")).scene;
  ASSERT_EQ(kinds(coil, MaterialKind::kMirror).size(), 1u);
  EXPECT_EQ(kinds(coil, MaterialKind::kMirror)[0]->albedo, float3(0.3f));
  Scene alag = load_collada_file(test::shared_scene("CBspheres_microfacet_al_ag.dae")).scene;
  auto metals = kinds(alag, MaterialKind::kMicrofacet);
  ASSERT_EQ(metals.size(), 2u);
  const Material* aluminium = metals[0]->alpha == 0.025f ? metals[0] : metals[1];
  EXPECT_EQ(aluminium->alpha, 0.025f);
  EXPECT_EQ(aluminium->eta, float3(1.3352f, 1.0109f, 0.68955f));
  EXPECT_EQ(aluminium->k, float3(7.3398f, 6.6157f, 5.6471f));
  Scene cu = load_collada_file(test::shared_scene("bunny_microfacet_cu.dae")).scene;
  ASSERT_EQ(kinds(cu, MaterialKind::kMicrofacet).size(), 1u);
  EXPECT_EQ(kinds(cu, MaterialKind::kMicrofacet)[0]->alpha, 0.1f);
}

TEST(Camera, ViewDirectionIsTheTransformedPointAndYFovComesFromTheAspect) {
  std::string libs = R"(<library_cameras><camera id="c"><optics><technique_common><perspective>
     <xfov>60</xfov><aspect_ratio>2</aspect_ratio><znear>0.5</znear><zfar>50</zfar>
     </perspective></technique_common></optics></camera></library_cameras>)";
  std::string nodes = R"(<node><translate>0 0 5</translate><instance_camera url="#c"/></node>)";
  Scene s = load_string(collada("Y_UP", libs, nodes)).scene;
  expect_near(s.camera.view_dir, {0, 0, 1});  // normalise((0,0,-1) + (0,0,5))
  EXPECT_FLOAT_EQ(s.camera.hfov_deg, 60.0f);
  EXPECT_NEAR(s.camera.vfov_deg, 2 * std::atan(std::tan(30 * M_PI / 180) / 2) * 180 / M_PI, 1e-4);
  EXPECT_FLOAT_EQ(s.camera.near_clip, 0.5f);
  EXPECT_FLOAT_EQ(s.camera.far_clip, 50.0f);
}

// ------------------------------------------------------------- malformed files

struct Malformed {
  const char* name;
  std::string xml;
  const char* element;  ///< must appear in the message
  const char* problem;  ///< must appear in the message
};

std::string mesh_with(const std::string& array, const std::string& prim) {
  return collada("Y_UP",
                 R"(<library_geometries><geometry id="g"><mesh><source id="p">)" + array +
                     R"(</source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices>)" + prim +
                     "</mesh></geometry></library_geometries>",
                 R"(<node id="n"><instance_geometry url="#g"/></node>)");
}

const std::string kGoodArray = R"(<float_array id="a" count="9">0 0 0 1 0 0 0 1 0</float_array>)";
const std::string kGoodPrim =
    R"(<triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>)";

std::vector<Malformed> malformed_cases() {
  std::string good = mesh_with(kGoodArray, kGoodPrim);
  return {
      {"truncated", good.substr(0, good.size() / 2), "test.dae:", "malformed XML"},
      {"wrong_root", "<?xml version=\"1.0\"?><scene/>", "test.dae", "expected <COLLADA>"},
      {"missing_float_array", mesh_with("", kGoodPrim), "<source id=\"p\">", "no <float_array>"},
      {"missing_p", mesh_with(kGoodArray, R"(<triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/>
          </triangles>)"),
       "<triangles", "no <p>"},
      {"index_out_of_range", mesh_with(kGoodArray, R"(<triangles count="1"><input semantic="VERTEX" source="#v"
          offset="0"/><p>0 1 3</p></triangles>)"),
       "<p>", "out of range"},
      {"negative_index", mesh_with(kGoodArray, R"(<triangles count="1"><input semantic="VERTEX" source="#v"
          offset="0"/><p>0 -1 2</p></triangles>)"),
       "<p>", "negative"},
      {"array_count_lies", mesh_with(R"(<float_array id="a" count="12">0 0 0 1 0 0 0 1 0</float_array>)", kGoodPrim),
       "<float_array id=\"a\">", "count=\"12\""},
      {"absurd_triangle_count", mesh_with(kGoodArray, R"(<triangles count="999999999"><input semantic="VERTEX"
          source="#v" offset="0"/><p>0 1 2</p></triangles>)"),
       "<triangles", "count"},
      {"nan_position", mesh_with(R"(<float_array id="a" count="9">0 0 0 nan 0 0 0 1 0</float_array>)", kGoodPrim),
       "<float_array id=\"a\">", "non-finite"},
      {"inf_matrix", collada("Y_UP", kTriangleGeometry, R"(<node id="n"><matrix>1 0 0 inf 0 1 0 0 0 0 1 0 0 0 0 1
          </matrix><instance_geometry url="#tri"/></node>)"),
       "<matrix>", "non-finite"},
      {"zero_sphere_radius",
       collada("Y_UP", R"(<library_geometries><geometry id="sph"><extra><technique
          profile="CGL"><sphere><radius>0</radius></sphere></technique></extra></geometry></library_geometries>)",
               R"(<node><instance_geometry url="#sph"/></node>)"),
       "<radius>", "positive"},
      {"duplicate_id", collada("Y_UP", kTriangleGeometry, R"(<node id="tri"/>)"), "<node id=\"tri\">",
       "already defined"},
      {"degenerate_area_light", collada("Y_UP", kLights, R"(<node><scale>0 1 1</scale>
          <instance_light url="#area"/></node>)"),
       "<area>", "zero area"},
      {"node_cycle",
       collada("Y_UP", R"(<library_nodes><node id="loop"><instance_node url="#loop"/></node>
          </library_nodes>)",
               R"(<node><instance_node url="#loop"/></node>)"),
       "<node id=\"loop\">", "cycle"},
      {"dangling_reference", collada("Y_UP", "", R"(<node><instance_geometry url="#nothing"/></node>)"),
       "<instance_geometry url=\"#nothing\">", "no element defines"},
  };
}

TEST(Malformed, EachFailsWithOneLineNamingFileAndElement) {
  for (const Malformed& m : malformed_cases()) {
    SCOPED_TRACE(m.name);
    try {
      load_string(m.xml, "test.dae");
      ADD_FAILURE() << "loaded without error";
    } catch (const InputError& e) {
      std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_EQ(msg.rfind("test.dae", 0), 0u) << msg;
      EXPECT_NE(msg.find(m.element), std::string::npos) << msg;
      EXPECT_NE(msg.find(m.problem), std::string::npos) << msg;
    }
  }
}

TEST(Malformed, VeryDeepNestingIsRefusedWithoutExhaustingTheStack) {
  std::string nodes;
  for (int i = 0; i < 5000; ++i) nodes += "<node>";
  for (int i = 0; i < 5000; ++i) nodes += "</node>";
  try {
    load_string(collada("Y_UP", "", nodes));
    ADD_FAILURE();
  } catch (const InputError& e) { EXPECT_NE(std::string(e.what()).find("nest deeper"), std::string::npos) << e.what(); }
}

TEST(Malformed, DirectoryAndMissingFile) {
  EXPECT_THROW(load_collada_file(std::filesystem::temp_directory_path()), InputError);
  EXPECT_THROW(load_collada_file("/nonexistent/scene.dae"), InputError);
}

TEST(EmptyScene, LoadsWithAWarning) {
  LoadResult r = load_string(collada("Y_UP", "", ""));
  EXPECT_EQ(r.scene.primitive_count(), 0u);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("renders black"), std::string::npos);
}

TEST(ProjectScenes, DefaultSceneLoads) {
  LoadResult r = load_collada_file(test::project_scene("cornell_spheres.dae"));
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.scene.mesh_triangle_count, 10u);
  EXPECT_EQ(r.scene.spheres.size(), 2u);
  EXPECT_EQ(r.scene.area_lights.size(), 1u);
}

}  // namespace
}  // namespace pt
