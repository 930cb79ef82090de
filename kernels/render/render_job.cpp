// RenderOutput's construction, copies, moves and destruction, compiled once (render_job.h).
#include "kernels/render/render_job.h"

namespace pt {

RenderOutput::RenderOutput() = default;
RenderOutput::RenderOutput(const RenderOutput&) = default;
RenderOutput::RenderOutput(RenderOutput&&) noexcept = default;
RenderOutput& RenderOutput::operator=(const RenderOutput&) = default;
RenderOutput& RenderOutput::operator=(RenderOutput&&) noexcept = default;
RenderOutput::~RenderOutput() = default;

}  // namespace pt
