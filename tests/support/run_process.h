// Running the pathtracer binary from tests: arguments, working directory,
// captured stdout and stderr, a time limit, and a scratch directory per test
// so that "no output file was created" can be checked by listing it; or in
// the background (a server), its output collected while the test talks to it.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace pt::test {

struct ProcessResult {
  int exit_code = -1;         ///< exit status, or 128 + signal number
  bool timed_out = false;     ///< killed after the time limit
  std::string out, err;       ///< everything written to stdout and stderr
  size_t peak_rss_bytes = 0;  ///< the child's maximum resident set size (wait4)
};

/// Runs `program` with `args` in `cwd`, killing it after `timeout_seconds`
/// (a limit against hangs, never a check of speed). When `memory_limit_bytes`
/// > 0 the child's address space is capped (not under AddressSanitizer, whose
/// shadow memory needs terabytes of it). `environment` ("NAME=VALUE" entries)
/// is added to the child's environment, e.g. a test hook such as
/// PT_TEST_SIGINT_AFTER_PASS. The tests' one way to run a program.
ProcessResult run_process(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& cwd, double timeout_seconds, size_t memory_limit_bytes = 0,
                          const std::vector<std::string>& environment = {});

/// A program started in the background (standard input /dev/null), whose
/// stdout and stderr a thread collects; killed on destruction if still running.
class BackgroundProcess {
 public:
  BackgroundProcess(const std::string& program, const std::vector<std::string>& args, const std::filesystem::path& cwd);
  ~BackgroundProcess();
  BackgroundProcess(const BackgroundProcess&) = delete;
  BackgroundProcess& operator=(const BackgroundProcess&) = delete;

  /// The first stdout line containing `text`, waiting up to `limit`; "" if none came.
  std::string wait_for_line(const std::string& text, std::chrono::milliseconds limit);
  /// Everything written to stdout / stderr so far.
  std::string out();
  std::string err();
  /// Sends `signal`, waits up to `limit` for the exit (then kills), and returns all it wrote.
  ProcessResult stop(int signal, std::chrono::milliseconds limit);

 private:
  int pid_ = -1;
  int out_fd_ = -1, err_fd_ = -1;
  std::mutex mutex_;
  std::string out_, err_;
  bool ended_ = false;
  std::thread reader_;
};

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
