// What a finished render leaves behind: the image, the sample-rate image
// (adaptive sampling), the variance image and camera file when asked for,
// the estimated-error image, the .partial image of an interrupted render, and
// the end-of-render report with the render's own error estimate.
#pragma once

#include <filesystem>
#include <string>

#include "cli_options.h"
#include "io/image_output.h"
#include "kernels/scene/camera.h"
#include "kernels/render/film.h"
#include "kernels/render/render_job.h"

namespace pt::cli {

/// How PNG values are quantised: truncated with --cs184-compat, else to the nearest.
PngQuantization png_quantization(const Options& o);

/// out.png -> out.partial.png
std::filesystem::path partial_path(const std::filesystem::path& p);

/// Checks every output the options ask for can be written (InputError if not).
void check_outputs_writable(const Options& o, const std::filesystem::path& output);

/// Writes the image and what the options add to it (each atomically);
/// `pixel_error` is RenderOutput::pixel_error, for --error-image.
void write_outputs(const Options& o, const std::filesystem::path& output, const Film& film, const Camera& camera,
                   const std::vector<float>& pixel_error = {});

/// The one line scripts read: "estimated error: relative RMSE <x>, RMSE <y>",
/// or "estimated error: not available (...)" saying why.
std::string error_line(const ImageErrorEstimate& e, bool pass_based);

/// The course renderer's end-of-render line; `ranks` > 1 adds how many MPI
/// ranks rendered and their busy time summed.
void print_report(const Options& o, const RenderStats& stats, int ranks = 1, double rank_seconds = 0.0);

}  // namespace pt::cli
