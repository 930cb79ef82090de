// Running the pathtracer binary from tests: arguments, working directory,
// captured stdout and stderr, a time limit, and a scratch directory per test
// so that "no output file was created" can be checked by listing it.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pt::test {

struct ProcessResult {
  int exit_code = -1;         ///< exit status, or 128 + signal number
  bool timed_out = false;     ///< killed after the time limit
  std::string out, err;       ///< everything written to stdout and stderr
  size_t peak_rss_bytes = 0;  ///< the child's maximum resident set size (wait4)
};

/// Runs `program` with `args` in `cwd`, killing it after `timeout_seconds`.
/// When `memory_limit_bytes` > 0 the child's address space is capped (not
/// under AddressSanitizer, whose shadow memory needs terabytes of it). When
/// `interrupt_after_seconds` > 0 the child gets SIGINT after that long.
/// The tests' one way to run a program.
ProcessResult run_process(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& cwd, double timeout_seconds, size_t memory_limit_bytes = 0,
                          double interrupt_after_seconds = 0);

/// The lines of `text` (the last one without its '\n'); "" has none.
std::vector<std::string> lines_of(const std::string& text);

/// A fresh empty directory under the system temporary directory, removed
/// (with its contents) on destruction.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  /// Names of the entries, sorted (hidden temporary files included).
  std::vector<std::string> entries() const;
  /// Writes `bytes` to the file `name` in this directory and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& bytes) const;

 private:
  std::filesystem::path path_;
};

}  // namespace pt::test
