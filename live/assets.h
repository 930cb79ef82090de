// The page and its scripts, embedded in the binary when it is built
// (embed_assets.cmake turns live/assets/ into a source file): the server
// answers only these paths and the API's, and never reads a file to do so.
#pragma once

#include <span>
#include <string_view>

namespace pt::live {

struct Asset {
  std::string_view path;          ///< "/app.js"; the page itself is "/"
  std::string_view content_type;  ///< with its charset for text
  std::string_view bytes;
};

/// Every embedded file.
std::span<const Asset> embedded_assets();

}  // namespace pt::live
