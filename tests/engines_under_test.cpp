// The engine list: add an engine here and every engine-level test covers it.
#include "engines_under_test.h"

#include "tests/reference/reference_renderer.h"

namespace pt::test {

const std::vector<EngineUnderTest>& engines_under_test() {
  static const std::vector<EngineUnderTest> engines = {
      {"reference",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) { return reference::render_reference(s, c, rs); }},
  };
  return engines;
}

}  // namespace pt::test
