// Output files appear whole or not at all: bytes go to a temporary file in the
// destination's directory, which is then renamed over the destination.
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

}  // namespace pt
