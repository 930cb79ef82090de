// run_process: posix_spawn with stdout / stderr redirected to temporary files.
#include "pathtracer_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

extern char** environ;

namespace pt::test {
namespace {

std::string read_and_remove(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  in.close();
  std::filesystem::remove(p);
  return s.str();
}

}  // namespace

ProcessResult run_process(const std::string& binary, const std::vector<std::string>& args) {
  ProcessResult r;
  std::filesystem::path dir = std::filesystem::temp_directory_path();
  std::string stem = "pt_process_" + std::to_string(getpid()) + "_";
  std::filesystem::path out = dir / (stem + "out"), err = dir / (stem + "err");

  std::vector<std::string> all = {binary};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  pid_t pid = 0;
  int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return r;

  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.peak_rss_bytes = static_cast<size_t>(usage.ru_maxrss) * 1024;  // Linux: kilobytes
  r.out = read_and_remove(out);
  r.err = read_and_remove(err);
  return r;
}

}  // namespace pt::test
