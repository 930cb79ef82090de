// Temporary-file-and-rename output.
#include "atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "scene_error.h"

namespace pt {
namespace {

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path dir = path.parent_path();
  std::string name = std::string(".") + path.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                     std::to_string(counter.fetch_add(1));
  return dir.empty() ? std::filesystem::path(name) : dir / name;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what, int err) {
  throw InputError(path.string() + ": " + what + ": " + std::strerror(err));
}

int open_temporary(const std::filesystem::path& tmp) {
  return ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
}

}  // namespace

void check_writable(const std::filesystem::path& path) {
  std::error_code ec;
  if (path.filename().empty()) throw InputError(path.string() + ": output path names a directory, not a file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path.string() + ": output path is a directory");
  std::filesystem::path tmp = temporary_sibling(path);
  int fd = open_temporary(tmp);
  if (fd < 0) fail(path, "cannot write output here", errno);
  ::close(fd);
  ::unlink(tmp.c_str());
}

namespace {

/// Writes and syncs `bytes` to the new file `tmp`; removes it and throws on failure.
void write_temporary(const std::filesystem::path& path, const std::filesystem::path& tmp, std::string_view bytes) {
  int fd = open_temporary(tmp);
  if (fd < 0) fail(path, "cannot create output", errno);
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      int err = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      fail(path, "write failed", err);
    }
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    int err = errno;
    ::unlink(tmp.c_str());
    fail(path, "write failed", err);
  }
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
  StagedFile(path, bytes).publish(true);
}

StagedFile::StagedFile(const std::filesystem::path& path, std::string_view bytes)
    : path_(path), temporary_(temporary_sibling(path)) {
  write_temporary(path_, temporary_, bytes);
  staged_ = true;
}

StagedFile::~StagedFile() {
  if (staged_) ::unlink(temporary_.c_str());
}

bool StagedFile::publish(bool replace) {
  if (replace) {
    if (::rename(temporary_.c_str(), path_.c_str()) != 0) fail(path_, "cannot move output into place", errno);
    staged_ = false;
    return true;
  }
  if (::link(temporary_.c_str(), path_.c_str()) != 0) {
    if (errno == EEXIST) return false;
    fail(path_, "cannot move output into place", errno);
  }
  // The temporary name goes now, not in the destructor: once published, the
  // directory holds the file under its own name only (a caller may report the
  // file done before this object is destroyed).
  ::unlink(temporary_.c_str());
  staged_ = false;
  return true;
}

}  // namespace pt
