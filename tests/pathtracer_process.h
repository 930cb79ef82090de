// Runs the pathtracer binary as a child process for command-line tests:
// captures its exit code, standard output and standard error, and its peak
// resident set size as the kernel accounted it (wait4).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace pt::test {

struct ProcessResult {
  int exit_code = -1;        ///< 128 + signal when killed; -1 when it could not start
  std::string out, err;      ///< everything written to stdout / stderr
  size_t peak_rss_bytes = 0; ///< the child's maximum resident set size
};

/// Runs `binary` with `args` and waits for it.
ProcessResult run_process(const std::string& binary, const std::vector<std::string>& args);

}  // namespace pt::test
