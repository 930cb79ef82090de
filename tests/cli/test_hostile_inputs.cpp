// Hostile scene files through the pathtracer binary, table-driven (hostile
// requests to its live view: test_hostile_requests.cpp). A bad file
// must exit 1 with exactly one stderr line "error: FILE:LINE: <element>: ..."
// and create no output (the scratch directory holds only the scene). A file
// that is odd but usable (unknown light or material type, empty scene) must
// render with warnings. No case may crash, hang or allocate gigabytes: each
// runs with a time limit and, outside AddressSanitizer builds, 1 GiB of
// address space.
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <functional>

#include <gtest/gtest.h>

#include "io/image_output.h"
#include "support/run_process.h"

namespace pt {
namespace {

constexpr double kTimeLimit = 60.0;
constexpr size_t kMemoryLimit = size_t(1) << 30;

// ------------------------------------------------------------ file builders

std::string collada(const std::string& libraries, const std::string& nodes, const std::string& up = "Y_UP") {
  return "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
         "version=\"1.4.1\">\n<asset><up_axis>" +
         up + "</up_axis></asset>\n" + libraries + "\n<library_visual_scenes><visual_scene id=\"s\">\n" + nodes +
         "\n</visual_scene></library_visual_scenes>\n<scene><instance_visual_scene url=\"#s\"/></scene>\n"
         "</COLLADA>\n";
}

/// Geometry "g": a <source> holding `array`, then `primitive`.
std::string mesh_file(const std::string& array, const std::string& primitive) {
  return collada("<library_geometries><geometry id=\"g\"><mesh>\n<source id=\"p\">" + array +
                     "</source>\n<vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/></vertices>\n" +
                     primitive + "\n</mesh></geometry></library_geometries>\n" + std::string(R"(<library_lights>
<light id="sun"><technique_common><directional><color>1 1 1</color></directional></technique_common></light>
</library_lights>)"),
                 "<node id=\"n\"><instance_geometry url=\"#g\"/></node><node><instance_light url=\"#sun\"/></node>");
}

const std::string kArray = R"(<float_array id="a" count="9">0 0 0 1 0 0 0 1 0</float_array>)";
std::string array_of(const std::string& numbers, int count = 9) {
  return "<float_array id=\"a\" count=\"" + std::to_string(count) + "\">" + numbers + "</float_array>";
}
std::string triangles(const std::string& indices, const std::string& count = "1") {
  return "<triangles count=\"" + count + "\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>" + indices +
         "</p></triangles>";
}
const std::string kTriangle = triangles("0 1 2");
std::string good_mesh() { return mesh_file(kArray, kTriangle); }

const std::string kTriangleGeometry = R"(<library_geometries><geometry id="tri"><mesh>
<source id="tp"><float_array id="ta" count="9">0 0 0 1 0 0 0 1 0</float_array></source>
<vertices id="tv"><input semantic="POSITION" source="#tp"/></vertices>
<triangles count="1"><input semantic="VERTEX" source="#tv" offset="0"/><p>0 1 2</p></triangles>
</mesh></geometry></library_geometries>)";

/// Light "l" of the given technique_common body and optional CGL extra.
std::string light_library(const std::string& common, const std::string& cgl = "") {
  return "<library_lights><light id=\"l\"><technique_common>" + common + "</technique_common>" +
         (cgl.empty() ? "" : "<extra><technique profile=\"CGL\">" + cgl + "</technique></extra>") +
         "</light></library_lights>";
}
std::string lit_triangle(const std::string& lights, const std::string& light_node_transform = "") {
  return collada(kTriangleGeometry + lights, "<node><instance_geometry url=\"#tri\"/></node>\n<node>" +
                                                 light_node_transform + "<instance_light url=\"#l\"/></node>");
}
std::string sphere_file(const std::string& radius) {
  return collada(R"(<library_geometries><geometry id="ball"><extra><technique profile="CGL"><sphere><radius>)" +
                     radius + "</radius></sphere></technique></extra></geometry></library_geometries>" +
                     light_library("<point><color>1 1 1</color></point>"),
                 "<node><instance_geometry url=\"#ball\"/></node><node><translate>0 3 0</translate>"
                 "<instance_light url=\"#l\"/></node>");
}
std::string effect_file(const std::string& effect_body) {
  return collada(kTriangleGeometry + "<library_effects><effect id=\"e\">" + effect_body +
                     "</effect></library_effects><library_materials><material id=\"m\"><instance_effect url=\"#e\"/>"
                     "</material></library_materials>" +
                     light_library("<ambient><color>1 1 1</color></ambient>"),
                 "<node><instance_geometry url=\"#tri\"><bind_material><technique_common><instance_material "
                 "symbol=\"x\" target=\"#m\"/></technique_common></bind_material></instance_geometry></node>"
                 "<node><instance_light url=\"#l\"/></node>");
}
std::string nested(const std::string& open, const std::string& close, int depth, const std::string& inner = "") {
  std::string s;
  s.reserve((open.size() + close.size()) * depth + inner.size());
  for (int i = 0; i < depth; ++i) s += open;
  s += inner;
  for (int i = 0; i < depth; ++i) s += close;
  return s;
}
/// Library node n0 holds the triangle; n{i} instances n{i-1} twice: 2^levels triangles.
std::string instancing_explosion(int levels) {
  std::string lib = "<library_nodes><node id=\"n0\"><instance_geometry url=\"#tri\"/></node>";
  for (int i = 1; i <= levels; ++i)
    lib += "<node id=\"n" + std::to_string(i) + "\"><instance_node url=\"#n" + std::to_string(i - 1) +
           "\"/><node><translate>1 0 0</translate><instance_node url=\"#n" + std::to_string(i - 1) +
           "\"/></node></node>";
  return collada(kTriangleGeometry + lib + "</library_nodes>",
                 "<node><instance_node url=\"#n" + std::to_string(levels) + "\"/></node>");
}

// ------------------------------------------------------------- the table

enum class Outcome {
  kError,    ///< exit 1, one error line, no output
  kWarning,  ///< renders; `problem` is part of a warning line, or "" for no warnings at all
};

struct HostileFile {
  const char* name;
  std::function<std::string()> contents;
  Outcome outcome;
  std::string element;  ///< kError: the element the message names ("" for whole-file problems)
  std::string problem;  ///< a fragment of the message (kWarning: of one warning line)
};

std::vector<HostileFile> structure_cases() {
  return {
      {"truncated_xml",
       [] {
         std::string s = good_mesh();
         return s.substr(0, s.size() / 2);
       },
       Outcome::kError, "", "malformed XML"},
      {"empty_file", [] { return std::string(); }, Outcome::kError, "", "malformed XML"},
      {"binary_garbage", [] { return std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16); }, Outcome::kError, "",
       "malformed XML"},
      {"wrong_root", [] { return std::string("<?xml version=\"1.0\"?>\n<scene><node/></scene>\n"); }, Outcome::kError,
       "", "root element is <scene>, expected <COLLADA>"},
      {"missing_float_array", [] { return mesh_file("", kTriangle); }, Outcome::kError, "<source id=\"p\">",
       "has no <float_array>"},
      {"missing_p",
       [] {
         return mesh_file(kArray, R"(<triangles count="1"><input semantic="VERTEX" source="#v"
          offset="0"/></triangles>)");
       },
       Outcome::kError, "<triangles>", "has no <p> index list"},
      {"dangling_reference", [] { return collada("", "<node><instance_geometry url=\"#nothing\"/></node>"); },
       Outcome::kError, "<instance_geometry url=\"#nothing\">", "which no element defines"},
      {"duplicate_id", [] { return collada(kTriangleGeometry, "<node id=\"tri\"/>"); }, Outcome::kError,
       "<node id=\"tri\">", "is already defined on line"},
      {"node_cycle",
       [] {
         return collada(R"(<library_nodes><node id="loop"><node><instance_node url="#loop"/>
          </node></node></library_nodes>)",
                        "<node><instance_node url=\"#loop\"/></node>");
       },
       Outcome::kError, "<node id=\"loop\">", "node instances itself (a cycle)"},
      {"deep_node_nesting", [] { return collada(kTriangleGeometry, nested("<node>", "</node>", 5000)); },
       Outcome::kError, "<node>", "nodes nest deeper than 256 levels"},
      {"instancing_explosion_2^40", [] { return instancing_explosion(40); }, Outcome::kError, "<node>",
       "the scene expands to more than"},
      {"id_with_newline_and_escape",
       [] {
         return collada("",
                        "<node><instance_geometry url=\"#a&#10;b&#27;[31m\"/>"
                        "</node>");
       },
       Outcome::kError, "<instance_geometry url=\"#a\\x0ab\\x1b[31m\">", "which no element defines"},
      {"megabyte_attribute",
       [] { return collada("", "<node><instance_geometry url=\"#" + std::string(1 << 20, 'x') + "\"/></node>"); },
       Outcome::kError, "<instance_geometry url=\"#xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx...\">", "which no element defines"},
  };
}

std::vector<HostileFile> count_and_index_cases() {
  return {
      {"index_out_of_range", [] { return mesh_file(kArray, triangles("0 1 3")); }, Outcome::kError, "<p>",
       "vertex index 3 is out of range (3 positions)"},
      {"negative_index", [] { return mesh_file(kArray, triangles("0 -1 2")); }, Outcome::kError, "<p>",
       "negative index \"-1\""},
      {"index_beyond_uint32", [] { return mesh_file(kArray, triangles("0 1 99999999999999999999")); }, Outcome::kError,
       "<p>", "index \"99999999999999999999\" is out of range"},
      {"float_array_count_lies", [] { return mesh_file(array_of("0 0 0 1 0 0 0 1 0", 12), kTriangle); },
       Outcome::kError, "<float_array id=\"a\">", "count=\"12\" but it holds 9 numbers"},
      {"triangle_count_lies", [] { return mesh_file(kArray, triangles("0 1 2", "2")); }, Outcome::kError, "<triangles>",
       "count=\"2\" needs 6 indices but <p> holds 3"},
      {"absurd_triangle_count", [] { return mesh_file(kArray, triangles("0 1 2", "999999999")); }, Outcome::kError,
       "<triangles>", "count=\"999999999\" needs 2999999997 indices"},
      {"absurd_accessor_count",
       [] {
         return mesh_file(kArray + R"(<technique_common><accessor source="#a"
          count="4000000000" stride="3"/></technique_common>)",
                          kTriangle);
       },
       Outcome::kError, "<accessor source=\"#a\">", "count=\"4000000000\" is larger than the data it describes"},
      {"absurd_polygon_size",
       [] {
         return mesh_file(kArray, R"(<polylist count="1"><input semantic="VERTEX"
          source="#v" offset="0"/><vcount>4000000000</vcount><p>0 1 2</p></polylist>)");
       },
       Outcome::kError, "<vcount>", "polygon size 4000000000 is out of range"},
      {"count_with_40_digits", [] { return mesh_file(kArray, triangles("0 1 2", std::string(40, '9'))); },
       Outcome::kError, "<triangles>", "is larger than the data it describes"},
  };
}

std::vector<HostileFile> value_cases() {
  return {
      {"nan_position", [] { return mesh_file(array_of("0 0 0 nan 0 0 0 1 0"), kTriangle); }, Outcome::kError,
       "<float_array id=\"a\">", "non-finite number \"nan\""},
      {"infinite_position", [] { return mesh_file(array_of("0 0 0 1 0 0 0 -inf 0"), kTriangle); }, Outcome::kError,
       "<float_array id=\"a\">", "non-finite number \"-inf\""},
      {"position_beyond_float", [] { return mesh_file(array_of("0 0 0 1e39 0 0 0 1 0"), kTriangle); }, Outcome::kError,
       "<float_array id=\"a\">", "number \"1e39\" is out of float range"},
      {"position_beyond_coordinate_limit", [] { return mesh_file(array_of("0 0 0 1e30 0 0 0 1 0"), kTriangle); },
       Outcome::kError, "<instance_geometry url=\"#g\">", "exceeds the coordinate limit 1e15"},
      {"number_of_a_million_digits",
       [] { return mesh_file(array_of("0 0 0 1" + std::string(1000000, '0') + " 0 0 0 1 0"), kTriangle); },
       Outcome::kError, "<float_array id=\"a\">", "is out of float range"},
      {"nan_light_colour", [] { return lit_triangle(light_library("<point><color>1 NaN 1</color></point>")); },
       Outcome::kError, "<color>", "non-finite number \"NaN\""},
      {"infinite_diffuse_colour",
       [] {
         return effect_file(R"(<profile_COMMON><technique sid="c"><lambert><diffuse>
          <color>inf 0 0 1</color></diffuse></lambert></technique></profile_COMMON>)");
       },
       Outcome::kError, "<color>", "non-finite number \"inf\""},
      {"negative_ior",
       [] {
         return effect_file(R"(<extra><technique profile="CGL"><glass><ior>-1.5</ior></glass>
          </technique></extra>)");
       },
       Outcome::kError, "<ior>", "index of refraction must be in (0, 100]"},
      {"nan_transmittance",
       [] {
         return effect_file(R"(<extra><technique profile="CGL"><refraction><transmittance>nan 1 1
          </transmittance><ior>1.3</ior></refraction></technique></extra>)");
       },
       Outcome::kError, "<transmittance>", "non-finite"},
      {"zero_microfacet_alpha",
       [] {
         return effect_file(R"(<extra><technique profile="CGL"><microfacet><alpha>0</alpha>
          <eta>1 1 1</eta><k>3 3 3</k></microfacet></technique></extra>)");
       },
       Outcome::kError, "<alpha>", "alpha must be in (0, 10]"},
      {"microfacet_without_k",
       [] {
         return effect_file(R"(<extra><technique profile="CGL"><microfacet><alpha>0.1</alpha>
          <eta>1 1 1</eta></microfacet></technique></extra>)");
       },
       Outcome::kError, "<microfacet>", "has no <k>"},
      {"negative_emission",
       [] {
         return effect_file(R"(<extra><technique profile="CGL"><emission><radiance>-1 2 2
          </radiance></emission></technique></extra>)");
       },
       Outcome::kError, "<radiance>", "negative radiance"},
      {"nan_matrix",
       [] {
         return collada(kTriangleGeometry,
                        "<node><matrix>1 0 0 0 0 nan 0 0 0 0 1 0 0 0 0 1"
                        "</matrix><instance_geometry url=\"#tri\"/></node>");
       },
       Outcome::kError, "<matrix>", "non-finite number"},
      {"overflowing_transforms",
       [] {
         return collada(kTriangleGeometry, nested("<node><scale>1e30 1e30 1e30</scale>", "</node>", 3,
                                                  "<instance_geometry url=\"#tri\"/>"));
       },
       Outcome::kError, "<instance_geometry url=\"#tri\">", "exceeds the coordinate limit 1e15"},
      {"zero_sphere_radius", [] { return sphere_file("0"); }, Outcome::kError, "<radius>",
       "sphere radius must be positive"},
      {"negative_sphere_radius", [] { return sphere_file("-2"); }, Outcome::kError, "<radius>",
       "sphere radius must be positive"},
      {"zero_area_light",
       [] { return lit_triangle(light_library("", "<area><color>1 1 1</color></area>"), "<scale>0 1 1</scale>"); },
       Outcome::kError, "<area>", "zero area or a degenerate transform"},
      {"collinear_area_light",
       [] {
         return lit_triangle(light_library("", "<area><color>1 1 1</color></area>"),
                             "<matrix>1 1 0 0  1 1 0 0  0 0 1 0  0 0 0 1</matrix>");
       },
       Outcome::kError, "<area>", "zero area or a degenerate transform"},
      {"camera_fov_out_of_range",
       [] {
         return collada(kTriangleGeometry + R"(<library_cameras><camera id="c">
          <optics><technique_common><perspective><xfov>200</xfov></perspective></technique_common></optics>
          </camera></library_cameras>)",
                        "<node><instance_geometry url=\"#tri\"/></node><node><instance_camera "
                        "url=\"#c\"/></node>");
       },
       Outcome::kError, "<xfov>", "field of view must be between 0 and 180 degrees"},
  };
}

std::vector<HostileFile> warning_cases() {
  return {
      {"unknown_light_type", [] { return lit_triangle(light_library("<laser><color>1 1 1</color></laser>")); },
       Outcome::kWarning, "", "<light id=\"l\">: unknown light type <laser>; skipped"},
      {"spot_light", [] { return lit_triangle(light_library("<spot><color>1 1 1</color></spot>")); }, Outcome::kWarning,
       "", "<light id=\"l\">: spot lights are not supported; skipped"},
      {"unknown_material_type",
       [] {
         return effect_file(R"(<profile_COMMON><technique sid="c"><lambert><diffuse>
          <color>0.5 0.5 0.5 1</color></diffuse></lambert></technique></profile_COMMON><extra><technique
          profile="CGL"><velvet><sheen>1</sheen></velvet></technique></extra>)");
       },
       Outcome::kWarning, "",
       "<velvet>: CGL <velvet> material is not supported; rendered as Lambertian with its diffuse colour"},
      {"rough_glass",
       [] {
         return effect_file(R"(<profile_COMMON><technique sid="c"><lambert><diffuse>
          <color>0.5 0.5 0.5 1</color></diffuse></lambert></technique></profile_COMMON><extra><technique
          profile="CGL"><glass><roughness>0.2</roughness><ior>1.5</ior></glass></technique></extra>)");
       },
       Outcome::kWarning, "",
       "<roughness>: roughness is ignored: rendered as a smooth dielectric (as the course does)"},
      {"unknown_up_axis",
       [] { return collada(kTriangleGeometry, "<node><instance_geometry url=\"#tri\"/></node>", "W_UP"); },
       Outcome::kWarning, "", "<up_axis>: unknown up axis \"W_UP\"; using Y_UP"},
      {"empty_scene", [] { return collada("", ""); }, Outcome::kWarning, "",
       "the scene has no geometry; it renders black"},
      {"deep_xml_outside_the_scene", [] { return collada("<extra>" + nested("<a>", "</a>", 300000) + "</extra>", ""); },
       Outcome::kWarning, "", "the scene has no geometry; it renders black"},
      {"tiny_numbers_underflow_to_zero", [] { return mesh_file(array_of("1e-50 -1e-60 0 1 0 0 0 1 0"), kTriangle); },
       Outcome::kWarning, "", ""},
  };
}

/// A Blender 3.4 export: the triangle and light "l" with the `blender` technique `technique`, placed `copies` times.
std::string blender_light_file(const std::string& technique, int copies = 1) {
  std::string nodes = "<node><instance_geometry url=\"#tri\"/></node>";
  for (int i = 0; i < copies; ++i) nodes += "<node><instance_light url=\"#l\"/></node>";
  std::string file = collada(kTriangleGeometry +
                                 "<library_lights><light id=\"l\"><technique_common><point><color>10 10 10</color>"
                                 "</point></technique_common><extra><technique profile=\"blender\">" +
                                 technique + "</technique></extra></light></library_lights>",
                             nodes, "Z_UP");
  return file.replace(file.find("<asset>"), 7,
                      "<asset><contributor><authoring_tool>Blender 3.4.1</authoring_tool></contributor>");
}

std::vector<HostileFile> blender_cases() {
  const std::string point = "<type>0</type><energy>10</energy>";
  return {
      {"blender_negative_energy", [] { return blender_light_file("<type>0</type><energy>-5</energy>"); },
       Outcome::kError, "<energy>", "energy -5 is outside [0, 1e+12]"},
      {"blender_nan_energy", [] { return blender_light_file("<type>0</type><energy>nan</energy>"); }, Outcome::kError,
       "<energy>", "non-finite number \"nan\""},
      {"blender_absurd_energy", [] { return blender_light_file("<type>1</type><energy>1e30</energy>"); },
       Outcome::kError, "<energy>", "is outside [0, 1e+12]"},
      {"blender_unknown_light_type", [] { return blender_light_file("<type>7</type><energy>10</energy>"); },
       Outcome::kError, "<type>", "unknown Blender light type 7"},
      {"blender_light_without_type", [] { return blender_light_file("<energy>10</energy>"); }, Outcome::kError,
       "<technique>", "has no <type>"},
      {"blender_absurd_area_size",
       [] { return blender_light_file("<type>4</type><energy>10</energy><area_size>1e30</area_size>"); },
       Outcome::kError, "<area_size>", "area_size 1e+30 is outside [0, 1e+06]"},
      {"blender_zero_area_size",
       [] { return blender_light_file("<type>4</type><energy>10</energy><area_size>0</area_size>"); }, Outcome::kError,
       "<technique>", "zero area"},
      {"blender_unknown_area_shape",
       [] { return blender_light_file("<type>4</type><energy>10</energy><area_shape>3</area_shape>"); },
       Outcome::kError, "<area_shape>", "unknown area shape 3"},
      {"blender_negative_radius", [=] { return blender_light_file(point + "<area_size>-1</area_size>"); },
       Outcome::kError, "<area_size>", "area_size -1 is outside"},
      {"blender_spot_cone_of_500_degrees",
       [] { return blender_light_file("<type>2</type><energy>10</energy><spotsize>500</spotsize>"); }, Outcome::kError,
       "<spotsize>", "spotsize 500 is outside [0, 180]"},
      {"blender_spot_blend_nan",
       [] { return blender_light_file("<type>2</type><energy>10</energy><spotblend>nan</spotblend>"); },
       Outcome::kError, "<spotblend>", "non-finite number"},
      {"blender_negative_colour", [=] { return blender_light_file(point + "<red>-1</red>"); }, Outcome::kError, "<red>",
       "red -1 is outside"},
      {"blender_5000_lights", [=] { return blender_light_file(point, 5000); }, Outcome::kError, "<node>",
       "the scene expands to more than 4096 lights"},
      {"ambiguous_node_reference",
       [] {
         return collada(kTriangleGeometry +
                            "<library_nodes><node id=\"twin\"><instance_geometry url=\"#tri\"/>"
                            "</node><node id=\"twin\"/></library_nodes>",
                        "<node><instance_node url=\"#twin\"/></node>");
       },
       Outcome::kError, "<instance_node url=\"#twin\">", "which several <node> elements carry"},
      {"duplicate_unreferenced_node_ids",
       [] {
         return collada(kTriangleGeometry + light_library("<ambient><color>1 1 1</color></ambient>"),
                        "<node id=\"Sphere\"><instance_geometry url=\"#tri\"/></node><node id=\"Sphere\">"
                        "<instance_light url=\"#l\"/></node>");
       },
       Outcome::kWarning, "", "id(s) carried by more than one <node> (\"Sphere\", defined on lines"},
  };
}

std::vector<HostileFile> all_cases() {
  std::vector<HostileFile> all;
  for (auto group : {structure_cases, count_and_index_cases, value_cases, warning_cases, blender_cases})
    for (HostileFile& f : group()) all.push_back(std::move(f));
  return all;
}

// ------------------------------------------------------------- the checks

/// Renders `scene` at 8x8, 1 sample, into out.pfm in `dir`.
test::ProcessResult render(const test::ScratchDir& dir, const std::string& scene) {
  return test::run_process(PT_PATHTRACER_BINARY, {"-q", "-r", "8", "8", "-s", "1", "-f", "out.pfm", scene}, dir.path(),
                           kTimeLimit, kMemoryLimit);
}

/// Exit 1, exactly one stderr line "error: SCENE...", no file added to `dir`.
void expect_one_line_error(const test::ScratchDir& dir, const std::vector<std::string>& before,
                           const test::ProcessResult& r, const std::string& scene, const std::string& element,
                           const std::string& problem) {
  ASSERT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  std::vector<std::string> lines = test::lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  ASSERT_EQ(r.err.back(), '\n');
  const std::string& line = lines[0];
  std::printf("    %s\n", line.c_str());
  EXPECT_EQ(line.rfind("error: " + scene + ":", 0), 0u) << line;
  if (!element.empty()) { EXPECT_NE(line.find(": " + element + ": "), std::string::npos) << line; }
  EXPECT_NE(line.find(problem), std::string::npos) << line;
  EXPECT_LT(line.size(), 400u);
  EXPECT_EQ(dir.entries(), before) << "an output or temporary file was left behind";
}

void PrintTo(const HostileFile& f, std::ostream* os) { *os << f.name; }

class HostileFileTest : public ::testing::TestWithParam<HostileFile> {};

TEST_P(HostileFileTest, FailsCleanlyOrRendersWithWarnings) {
  const HostileFile& c = GetParam();
  test::ScratchDir dir;
  std::string scene = dir.write(std::string(c.name) + ".dae", c.contents()).string();
  std::vector<std::string> before = dir.entries();
  test::ProcessResult r = render(dir, scene);
  if (c.outcome == Outcome::kError) return expect_one_line_error(dir, before, r, scene, c.element, c.problem);

  ASSERT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (c.problem.empty()) { EXPECT_EQ(r.err, ""); }
  bool found = c.problem.empty();
  for (const std::string& line : test::lines_of(r.err)) {
    EXPECT_EQ(line.rfind("warning: " + scene, 0), 0u) << line;
    found |= line.find(c.problem) != std::string::npos;
    std::printf("    %s\n", line.c_str());
  }
  EXPECT_TRUE(found) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.pfm"));
}

INSTANTIATE_TEST_SUITE_P(Table, HostileFileTest, ::testing::ValuesIn(all_cases()), [](const auto& info) {
  std::string n = info.param.name;
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
});

TEST(HostileFile, EmptySceneRendersBlack) {
  test::ScratchDir dir;
  std::string scene = dir.write("empty.dae", collada("", "")).string();
  test::ProcessResult r = render(dir, scene);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int w = 0, h = 0;
  std::vector<float3> pixels = read_pfm(dir / "out.pfm", w, h);
  ASSERT_EQ(w, 8);
  ASSERT_EQ(h, 8);
  for (const float3& p : pixels) ASSERT_EQ(p, float3(0.0f));
}

// ------------------------------------------------- things that are not scenes

TEST(NotASceneFile, DirectoryMissingFileFifoAndDanglingLink) {
  test::ScratchDir dir;
  std::filesystem::create_directory(dir / "a_directory");
  ASSERT_EQ(mkfifo((dir / "a_fifo").c_str(), 0644), 0);
  std::filesystem::create_symlink(dir / "nowhere.dae", dir / "dangling.dae");
  struct Case {
    std::string path, problem;
  };
  for (const Case& c :
       {Case{(dir / "a_directory").string(), "is a directory, not a scene file"},
        Case{(dir / "missing.dae").string(), "no such file"}, Case{(dir / "a_fifo").string(), "is not a regular file"},
        Case{(dir / "dangling.dae").string(), "no such file"}, Case{"/dev/zero", "is not a regular file"}}) {
    SCOPED_TRACE(c.path);
    std::vector<std::string> before = dir.entries();
    test::ProcessResult r = render(dir, c.path);
    expect_one_line_error(dir, before, r, c.path, "", c.problem);
  }
}

TEST(NotASceneFile, UnreadableFile) {
  if (geteuid() == 0) GTEST_SKIP() << "running as root: permissions do not stop reading";
  test::ScratchDir dir;
  std::string scene = dir.write("locked.dae", good_mesh()).string();
  std::filesystem::permissions(scene, std::filesystem::perms::none);
  std::vector<std::string> before = dir.entries();
  expect_one_line_error(dir, before, render(dir, scene), scene, "", "cannot be opened for reading");
}

}  // namespace
}  // namespace pt
