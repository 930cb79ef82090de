// Checkpoint files: the accumulated state of a pass-based render, with a
// fingerprint of everything that decides the image (engine, scene, camera,
// settings), so a render resumes only where it would continue the same image.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "kernels/render/accumulation.h"
#include "kernels/scene/camera.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"

namespace pt {

/// One line describing what must match for a checkpoint to be resumed.
std::string render_fingerprint(const std::string& engine, const Scene& scene, const Camera& camera,
                               const RenderSettings& rs);

/// Writes atomically (temporary file, then rename).
void save_checkpoint(const std::filesystem::path& path, const std::string& fingerprint, const Accumulation& acc);

/// nullopt if `path` does not exist. Throws InputError if it is corrupt, was
/// written for a different render, does not hold `pixel_count` pixels, or
/// holds values no render of at most `max_samples` samples per pixel makes
/// (non-finite sums, more samples than that).
std::optional<Accumulation> load_checkpoint(const std::filesystem::path& path, const std::string& fingerprint,
                                            size_t pixel_count, uint32_t max_samples);

}  // namespace pt
