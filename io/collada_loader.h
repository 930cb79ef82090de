// Loads a CS184 COLLADA (.dae) scene into the flat scene model. Follows the
// course renderer's reading of the format (see ../shared/scenes/README.md and
// docs/cs184_compatibility.md).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "io/load_limits.h"
#include "kernels/scene/scene.h"

namespace pt {

struct LoadResult {
  Scene scene;
  std::vector<std::string> warnings;  ///< one line each, naming file and element
  double seconds = 0.0;
};

/// Throws InputError (one line: file, line, element, problem) on a bad file,
/// including one whose instancing expands beyond `limits`.
LoadResult load_collada_file(const std::filesystem::path& path, const LoadLimits& limits = {});

/// Same, from memory; `label` names the source in messages.
LoadResult load_collada_string(std::string_view xml, const std::string& label, const LoadLimits& limits = {});

/// One line: triangles, spheres, lights by type, bounds, load time.
std::string scene_summary(const LoadResult& r);

}  // namespace pt
