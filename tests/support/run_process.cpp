// run_process on fork / execv with poll() over both pipes; ScratchDir on mkdtemp.
#include "support/run_process.h"

#include <cerrno>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <thread>

extern char** environ;

namespace pt::test {
namespace {

/// This process's environment with `extra` ("NAME=VALUE") added, as execve
/// takes it; the strings live in `storage`. Built before fork: the child only execs.
std::vector<char*> environment_with(const std::vector<std::string>& extra, std::vector<std::string>& storage) {
  storage.clear();
  for (char** e = environ; *e; ++e) {
    std::string entry(*e);
    const std::string name = entry.substr(0, entry.find('=') + 1);
    if (std::none_of(extra.begin(), extra.end(), [&](const std::string& x) { return x.rfind(name, 0) == 0; }))
      storage.push_back(std::move(entry));
  }
  storage.insert(storage.end(), extra.begin(), extra.end());
  std::vector<char*> envp;
  for (std::string& entry : storage) envp.push_back(entry.data());
  envp.push_back(nullptr);
  return envp;
}

[[noreturn]] void exec_child(const std::string& program, const std::vector<std::string>& args,
                             const std::filesystem::path& cwd, int out_fd, int err_fd, size_t memory_limit,
                             char* const* envp) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  if (memory_limit > 0) {
    rlimit lim{memory_limit, memory_limit};
    setrlimit(RLIMIT_AS, &lim);
  }
  // Standard input is /dev/null: a child that reads it (mpirun forwards it to
  // rank 0) must not consume the input of whatever runs the tests.
  int null_fd = open("/dev/null", O_RDONLY);
  if (null_fd < 0 || dup2(null_fd, 0) < 0) _exit(126);
  if (chdir(cwd.c_str()) != 0 || dup2(out_fd, 1) < 0 || dup2(err_fd, 2) < 0) _exit(126);
  execve(program.c_str(), argv.data(), envp);
  _exit(127);
}

/// Reads both pipes until they close or the deadline passes; false on timeout.
bool drain(int out_fd, int err_fd, std::string& out, std::string& err, double timeout_seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  std::string* sinks[2] = {&out, &err};
  int open = 2;
  char buf[4096];
  while (open > 0) {
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    left = std::max(left, std::chrono::milliseconds(1));
    if (poll(fds, 2, static_cast<int>(left.count())) < 0) continue;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      ssize_t n = read(fds[i].fd, buf, sizeof buf);
      if (n > 0) {
        sinks[i]->append(buf, static_cast<size_t>(n));
      } else {
        fds[i].fd = -1;
        --open;
      }
    }
  }
  return true;
}

}  // namespace

ProcessResult run_process(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& cwd, double timeout_seconds, size_t memory_limit_bytes,
                          const std::vector<std::string>& environment) {
#ifdef PT_ADDRESS_SANITIZER  // ASan's shadow memory needs the address space
  memory_limit_bytes = 0;
#endif
  ProcessResult r;
  std::vector<std::string> env_storage;
  std::vector<char*> envp = environment_with(environment, env_storage);
  int out_pipe[2], err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0 || pipe2(err_pipe, O_CLOEXEC) != 0) return r;
  pid_t pid = fork();
  if (pid == 0) exec_child(program, args, cwd, out_pipe[1], err_pipe[1], memory_limit_bytes, envp.data());
  close(out_pipe[1]);
  close(err_pipe[1]);
  if (pid < 0) {
    close(out_pipe[0]);
    close(err_pipe[0]);
    return r;
  }
  r.timed_out = !drain(out_pipe[0], err_pipe[0], r.out, r.err, timeout_seconds);
  if (r.timed_out) kill(pid, SIGKILL);
  close(out_pipe[0]);
  close(err_pipe[0]);
  int status = 0;
  struct rusage usage {};
  while (wait4(pid, &status, 0, &usage) < 0) {
    if (errno != EINTR) return r;  // exit_code stays -1: not "exited 0"
  }
  r.peak_rss_bytes = static_cast<size_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

BackgroundProcess::BackgroundProcess(const std::string& program, const std::vector<std::string>& args,
                                     const std::filesystem::path& cwd) {
  int out_pipe[2], err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0 || pipe2(err_pipe, O_CLOEXEC) != 0) return;
  pid_t pid = fork();
  if (pid == 0) exec_child(program, args, cwd, out_pipe[1], err_pipe[1], 0, environ);
  close(out_pipe[1]);
  close(err_pipe[1]);
  out_fd_ = out_pipe[0];
  err_fd_ = err_pipe[0];
  pid_ = pid;
  reader_ = std::thread([this] {
    pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
    std::string* sinks[2] = {&out_, &err_};
    int open = 2;
    char buf[4096];
    while (open > 0) {
      if (poll(fds, 2, 100) < 0) continue;
      for (int i = 0; i < 2; ++i) {
        if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
        ssize_t n = read(fds[i].fd, buf, sizeof buf);
        std::lock_guard lock(mutex_);
        if (n > 0) {
          sinks[i]->append(buf, static_cast<size_t>(n));
        } else {
          fds[i].fd = -1;
          --open;
        }
      }
    }
    std::lock_guard lock(mutex_);
    ended_ = true;
  });
}

BackgroundProcess::~BackgroundProcess() {
  if (pid_ > 0) stop(SIGKILL, std::chrono::milliseconds(10000));
}

std::string BackgroundProcess::wait_for_line(const std::string& text, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      for (size_t start = 0, end; (end = out_.find('\n', start)) != std::string::npos; start = end + 1)
        if (out_.substr(start, end - start).find(text) != std::string::npos) return out_.substr(start, end - start);
      if (ended_ || std::chrono::steady_clock::now() > deadline) return "";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::string BackgroundProcess::out() {
  std::lock_guard lock(mutex_);
  return out_;
}

std::string BackgroundProcess::err() {
  std::lock_guard lock(mutex_);
  return err_;
}

ProcessResult BackgroundProcess::stop(int signal, std::chrono::milliseconds limit) {
  ProcessResult r;
  if (pid_ <= 0) return r;
  kill(pid_, signal);
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  pid_t done = 0;
  while ((done = waitpid(pid_, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (done == 0) {
    r.timed_out = true;
    kill(pid_, SIGKILL);
    waitpid(pid_, &status, 0);
  }
  pid_ = -1;
  reader_.join();
  close(out_fd_);
  close(err_fd_);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = out();
  r.err = err();
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

ScratchDir::ScratchDir() {
  std::string templ = (std::filesystem::temp_directory_path() / "pt_test_XXXXXX").string();
  if (mkdtemp(templ.data()) != nullptr) path_ = templ;
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  if (!path_.empty()) {
    // Restore permissions a test may have removed, so that removal succeeds.
    for (const auto& e : std::filesystem::recursive_directory_iterator(path_, ec))
      std::filesystem::permissions(e.path(), std::filesystem::perms::owner_all, std::filesystem::perm_options::add, ec);
    std::filesystem::remove_all(path_, ec);
  }
}

std::vector<std::string> ScratchDir::entries() const {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(path_)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::filesystem::path ScratchDir::write(const std::string& name, const std::string& bytes) const {
  std::filesystem::path p = path_ / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

}  // namespace pt::test
