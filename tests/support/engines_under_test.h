// The render engines that engine-level tests run against. Every light-transport
// test iterates this list, so an engine joins the whole suite by being listed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "kernels/render/render_job.h"

namespace pt::test {

using RenderFn = std::function<RenderOutput(const Scene&, const Camera&, const RenderSettings&)>;

struct EngineUnderTest {
  std::string name;
  RenderFn render;
};

/// The reference renderer (midpoint BVH) first, then the SIMD engines.
const std::vector<EngineUnderTest>& engines_under_test();

}  // namespace pt::test
