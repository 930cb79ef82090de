// Request parameters are read strictly: the table lists values that must be
// refused (with a message naming the parameter) and values that must read.
#include <cmath>

#include <gtest/gtest.h>

#include "live/request_params.h"
#include "live/view_settings.h"

namespace pt::live {
namespace {

using Map = RequestParams::Map;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ParamError& e) { return e.what(); }
  return "";
}

TEST(RequestParams, NumbersMustBeWholeFiniteDecimalsInRange) {
  for (const char* bad : {"", "nan", "NaN", "inf", "-inf", "1e999", "0x10", "1.5.2", "1,5", " 1", "1 ", "+1", "1e",
                          "--1", ".", "e5", "100001", "-100001", "１"}) {
    Map m{{"dx", bad}};
    std::string e = error_of([&] { RequestParams(m, {"dx"}).number("dx", -1e5, 1e5); });
    EXPECT_NE(e.find("dx: must be a number from"), std::string::npos) << "\"" << bad << "\": " << e;
  }
  for (auto [text, value] : {std::pair{"0", 0.0}, std::pair{"-12.5", -12.5}, std::pair{"1e3", 1000.0},
                             std::pair{".5", 0.5}, std::pair{"5.", 5.0}, std::pair{"-0", 0.0}}) {
    Map m{{"dx", text}};
    EXPECT_EQ(RequestParams(m, {"dx"}).number("dx", -1e5, 1e5), value) << text;
  }
}

TEST(RequestParams, IntegersVectorsChoicesAndFileNames) {
  Map m{{"n", "12"}, {"v", "1,-2.5,3e2"}, {"c", "pan"}, {"f", "my_cam-2.txt"}};
  RequestParams p(m, {"n", "v", "c", "f"});
  EXPECT_EQ(p.integer("n", 0, 100), 12);
  EXPECT_EQ(p.vector("v", 1e3f), float3(1.0f, -2.5f, 300.0f));
  constexpr std::array<const char*, 2> ops = {"orbit", "pan"};
  EXPECT_EQ(p.choice("c", ops), 1u);
  EXPECT_EQ(p.file_name("f", ".txt"), "my_cam-2.txt");
  for (const char* bad : {"1.0", "1e2", "-1", "101", "0x1", "12 ", "99999999999999999999"}) {
    Map b{{"n", bad}};
    EXPECT_NE(error_of([&] { RequestParams(b, {"n"}).integer("n", 0, 100); }), "") << bad;
  }
  for (const char* bad : {"1,2", "1,2,3,4", "nan,0,0", "1,,2", "1e20,0,0", "1;2;3", ""}) {
    Map b{{"v", bad}};
    EXPECT_NE(error_of([&] { RequestParams(b, {"v"}).vector("v", 1e15f); }), "") << bad;
  }
  const std::string long_name = std::string(70, 'a') + ".txt";
  for (const std::string& bad :
       {std::string("../x.txt"), std::string("/etc/passwd.txt"), std::string("a/b.txt"), std::string(".txt"),
        std::string(".hidden.txt"), std::string("x.png"), std::string("x.txt/"), std::string("a b.txt"),
        std::string("x.txt\n"), std::string("%2e%2e.txt"), std::string("-rf.txt"), std::string("--help.txt"),
        long_name}) {
    Map b{{"f", bad}};
    EXPECT_NE(error_of([&] { RequestParams(b, {"f"}).file_name("f", ".txt"); }), "") << bad;
  }
}

TEST(RequestParams, UnknownRepeatedAndMissingNamesAreRefused) {
  Map unknown{{"dx", "1"}, {"evil", "1"}};
  EXPECT_EQ(error_of([&] { RequestParams(unknown, {"dx"}); }), "unknown parameter \"evil\"");
  Map twice{{"dx", "1"}, {"dx", "2"}};
  EXPECT_EQ(error_of([&] { RequestParams(twice, {"dx"}); }), "parameter \"dx\" is given more than once");
  Map none;
  EXPECT_EQ(error_of([&] { RequestParams(none, {"dx"}).number("dx", 0, 1); }), "missing parameter \"dx\"");
  Map control{{"dx", "1\x1b[31m"}};
  std::string e = error_of([&] { RequestParams(control, {"dx"}).number("dx", 0, 10); });
  EXPECT_NE(e.find("\\x1b[31m"), std::string::npos) << e;  // control bytes escaped: one clean log line
}

TEST(ViewSettings, ProblemsAreNamed) {
  ViewSettings s;
  EXPECT_EQ(view_settings_problem(s), "");
  s.width = 4096;
  s.height = 4096;
  EXPECT_NE(view_settings_problem(s).find("at most 4194304 pixels"), std::string::npos);
  s = ViewSettings{};
  s.samples = 0;
  EXPECT_NE(view_settings_problem(s).find("samples"), std::string::npos);
  s = ViewSettings{};
  s.adaptive_tolerance = std::nanf("");
  EXPECT_NE(view_settings_problem(s).find("adaptive tolerance"), std::string::npos);
  s = ViewSettings{};
  s.preview = 3;
  EXPECT_NE(view_settings_problem(s).find("preview"), std::string::npos);
}

TEST(ViewSettings, TheCommandLinesSettingsRoundTrip) {
  RenderSettings rs;
  rs.width = 123;
  rs.height = 45;
  rs.samples_per_pixel = 77;
  rs.light_samples = 3;
  rs.max_depth = 6;
  rs.shading = ShadingMode::kNormals;
  rs.bounces = BounceMode::kIndirectOnly;
  rs.direct = DirectLighting::kHemisphere;
  rs.adaptive_tolerance = 0.05f;
  rs.adaptive_batch = 8;
  rs.seed = 9;
  RenderSettings back = render_settings(rs, view_settings_of(rs), rs.width, rs.height);
  EXPECT_EQ(back.samples_per_pixel, 77);
  EXPECT_EQ(back.light_samples, 3);
  EXPECT_EQ(back.max_depth, 6);
  EXPECT_EQ(back.shading, ShadingMode::kNormals);
  EXPECT_EQ(back.bounces, BounceMode::kIndirectOnly);
  EXPECT_EQ(back.direct, DirectLighting::kHemisphere);
  EXPECT_EQ(back.adaptive_tolerance, 0.05f);
  EXPECT_EQ(back.adaptive_batch, 8);
  EXPECT_EQ(back.seed, 9u);
  EXPECT_EQ(back.width, 123);
}

}  // namespace
}  // namespace pt::live
