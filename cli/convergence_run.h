// --reference REF.pfm --convergence-csv OUT.csv: render at 1, 2, 4, ... samples
// per pixel up to -s and log, after each doubling, the wall time, samples,
// rays traced and the error against the reference image (RMSE, relative MSE,
// mean bias) as CSV. Pass-based engines continue from the previous doubling;
// the reference engine renders each count from scratch.
#pragma once

#include <atomic>

#include "cli_options.h"
#include "render_engines.h"

namespace pt::cli {

/// Returns the process exit code. `cancel` stops early (the CSV keeps the rows done).
int run_convergence(const Options& o, const EngineRunner& engine, const std::atomic<bool>& cancel);

}  // namespace pt::cli
