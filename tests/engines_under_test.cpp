// The engine list: add an engine here and every engine-level test covers it.
#include "engines_under_test.h"

#include "tests/reference/reference_renderer.h"
#include "wavefront/megakernel_renderer.h"
#include "wavefront/tracers.h"
#include "wavefront/wavefront_renderer.h"

namespace pt::test {

const std::vector<EngineUnderTest>& engines_under_test() {
  static const std::vector<EngineUnderTest> engines = {
      {"reference",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) { return reference::render_reference(s, c, rs); }},
      {"wavefront",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) {
         SceneBvh4 bvh(s);
         return wf::render_wavefront(s, c, rs, wf::Bvh4Tracer<>{bvh});
       }},
      {"megakernel",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) {
         SceneBvh4 bvh(s);
         return wf::render_megakernel(s, c, rs, wf::Bvh4Tracer<>{bvh});
       }},
  };
  return engines;
}

}  // namespace pt::test
