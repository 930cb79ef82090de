// libFuzzer entry point for the COLLADA loader. Every input must either load
// into a scene that satisfies scene_invariant_violation(), with one-line
// warnings, and renders a tiny image of finite, non-negative pixels with the
// reference renderer; or throw pt::InputError with a one-line message naming
// the file. Anything else (another exception, a sanitizer report, a violated
// invariant) aborts, which libFuzzer and the regression replay report.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/camera_setup.h"
#include "io/collada_loader.h"
#include "io/scene_error.h"
#include "scene_invariants.h"
#include "reference/reference_renderer.h"

namespace {

constexpr const char* kLabel = "fuzz.dae";

/// Smaller than the defaults so that no input can spend seconds building a
/// legitimately huge scene; the limit checks themselves are what is fuzzed.
pt::LoadLimits fuzz_limits() {
  pt::LoadLimits l;
  l.max_instances = 1 << 14;
  l.max_vertices = 1 << 16;
  l.max_primitives = 1 << 16;
  return l;
}

[[noreturn]] void violation(const char* what, const std::string& detail, const std::string& text) {
  std::fprintf(stderr, "fuzz_collada_loader: %s: %s\n  in: %s\n", what, detail.c_str(), text.c_str());
  std::abort();
}

/// Empty if a 4x3, 2-sample, 3-bounce reference render of `scene` has only
/// finite, non-negative pixels.
std::string render_violation(const pt::Scene& scene) {
  pt::RenderSettings rs{.width = 4, .height = 3, .samples_per_pixel = 2, .max_depth = 3, .adaptive_tolerance = 0.0f};
  pt::Camera camera = pt::resolve_camera(scene, rs.width, rs.height);
  pt::RenderOutput out = pt::reference::render_reference(scene, camera, rs);
  for (const pt::float3& p : out.film.radiance)
    if (!pt::is_finite(p) || p.x < 0 || p.y < 0 || p.z < 0) return "a pixel is negative or not finite";
  return {};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view xml(reinterpret_cast<const char*>(data), size);
  try {
    pt::LoadResult r = pt::load_collada_string(xml, kLabel, fuzz_limits());
    if (std::string v = pt::fuzz::scene_invariant_violation(r.scene); !v.empty())
      violation("scene invariant violated", v, pt::scene_summary(r));
    for (const std::string& w : r.warnings)
      if (std::string v = pt::fuzz::message_violation(w, kLabel); !v.empty()) violation("bad warning", v, w);
    if (std::string v = render_violation(r.scene); !v.empty()) violation("bad render", v, pt::scene_summary(r));
  } catch (const pt::InputError& e) {
    if (std::string v = pt::fuzz::message_violation(e.what(), kLabel); !v.empty())
      violation("bad error message", v, e.what());
  }
  return 0;
}
