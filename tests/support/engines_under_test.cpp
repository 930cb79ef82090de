// The engine list: add an engine here and every engine-level test covers it.
#include "support/engines_under_test.h"

#include "reference/reference_renderer.h"
#include "bvh/scene_bvh4.h"
#include "wavefront/engines.h"

namespace pt::test {

const std::vector<EngineUnderTest>& engines_under_test() {
  static const std::vector<EngineUnderTest> engines = {
      {"reference",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) { return reference::render_reference(s, c, rs); }},
      {"wavefront",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) {
         SceneBvh4 bvh(s);
         return wf::render_wavefront(s, c, rs, wf::Tracing{.bvh4 = &bvh});
       }},
      {"megakernel",
       [](const Scene& s, const Camera& c, const RenderSettings& rs) {
         SceneBvh4 bvh(s);
         return wf::render_megakernel(s, c, rs, wf::Tracing{.bvh4 = &bvh});
       }},
  };
  return engines;
}

}  // namespace pt::test
