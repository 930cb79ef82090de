// libFuzzer entry point for the COLLADA loader. Every input must either load
// into a scene that satisfies scene_invariant_violation(), with one-line
// warnings, or throw pt::InputError with a one-line message naming the file.
// Anything else (another exception, a sanitizer report, a violated
// invariant) aborts, which libFuzzer and the regression replay report.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/collada_loader.h"
#include "io/scene_error.h"
#include "scene_invariants.h"

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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view xml(reinterpret_cast<const char*>(data), size);
  try {
    pt::LoadResult r = pt::load_collada_string(xml, kLabel, fuzz_limits());
    if (std::string v = pt::fuzz::scene_invariant_violation(r.scene); !v.empty())
      violation("scene invariant violated", v, pt::scene_summary(r));
    for (const std::string& w : r.warnings)
      if (std::string v = pt::fuzz::message_violation(w, kLabel); !v.empty()) violation("bad warning", v, w);
  } catch (const pt::InputError& e) {
    if (std::string v = pt::fuzz::message_violation(e.what(), kLabel); !v.empty())
      violation("bad error message", v, e.what());
  }
  return 0;
}
