// The one way the program reads a whole input file (scene, camera file,
// checkpoint, PFM reference): only regular files (a FIFO would block the
// read forever, a device can be endless), up to a size limit, with one error
// line naming the file and the problem.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace pt {

/// The bytes of `path`. `what` names the kind of file in messages ("scene
/// file", "camera file", ...). Throws InputError: "<path>: no such file",
/// "<path>: is a directory, not a <what>", "<path>: is not a regular file",
/// "<path>: is larger than <limit>; not a <what>", "<path>: cannot be opened
/// for reading", "<path>: read failed".
std::string read_regular_file(const std::filesystem::path& path, std::string_view what, uint64_t max_bytes);

}  // namespace pt
