// Output files appear whole or not at all: bytes go to a temporary file in the
// destination's directory, which is then renamed over the destination, or
// linked to it where an existing file must not be replaced.
#pragma once

#include <filesystem>
#include <string_view>

namespace pt {

/// Throws InputError if `path` cannot be written (missing or read-only
/// directory, or a directory in the way). Leaves nothing behind.
void check_writable(const std::filesystem::path& path);

/// Writes `bytes` to a temporary file next to `path` and renames it into place.
/// Throws InputError on failure, after removing the temporary file.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

/// A file written whole (and synced) to a temporary file beside `path`, not yet
/// in place: publish() puts it there; the destructor removes the temporary file.
class StagedFile {
 public:
  /// Throws InputError when the temporary file cannot be written.
  StagedFile(const std::filesystem::path& path, std::string_view bytes);
  ~StagedFile();
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;

  /// Puts the file at its path: renamed over whatever is there (`replace`), or
  /// linked there only if no file of that name exists (false then, and nothing
  /// changes). Once it returns true, no temporary name is left. Throws
  /// InputError on other failures.
  bool publish(bool replace);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_, temporary_;
  bool staged_ = false;  ///< the temporary file exists
};

}  // namespace pt
