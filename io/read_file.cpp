// read_regular_file.
#include "read_file.h"

#include <fstream>

#include "scene_error.h"

namespace pt {
namespace {

std::string size_text(uint64_t bytes) {
  if (bytes % (uint64_t(1) << 30) == 0) return std::to_string(bytes >> 30) + " GiB";
  if (bytes % (uint64_t(1) << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

std::string read_regular_file(const std::filesystem::path& path, std::string_view what, uint64_t max_bytes) {
  const std::string name = path.string();
  std::error_code ec;
  auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw InputError(name + ": no such file");
  if (std::filesystem::is_directory(status)) throw InputError(name + ": is a directory, not a " + std::string(what));
  if (!std::filesystem::is_regular_file(status)) throw InputError(name + ": is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot be opened for reading");
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  if (size < 0) throw InputError(name + ": read failed");
  if (static_cast<uint64_t>(size) > max_bytes)
    throw InputError(name + ": is larger than " + size_text(max_bytes) + "; not a " + std::string(what));
  in.seekg(0);
  std::string bytes(static_cast<size_t>(size), '\0');
  if (!in.read(bytes.data(), size)) throw InputError(name + ": read failed");
  return bytes;
}

}  // namespace pt
