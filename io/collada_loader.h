// Loads a CS184 COLLADA (.dae) scene into the flat scene model. Follows the
// course renderer's reading of the format (see ../shared/scenes/README.md and
// docs/cs184_compatibility.md); a file that Blender 2.80 or later exported is
// read as Blender and Cycles mean it (docs/blender_scenes.md).
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
  /// What was loaded, one line per node that placed something (mesh, sphere,
  /// light, camera), in the file's order, after a line saying how the file
  /// was read: for --scene-info, to check against Blender's outliner.
  std::vector<std::string> contents;
  double seconds = 0.0;
};

/// Throws InputError (one line: file, line, element, problem) on a bad file,
/// including one whose instancing expands beyond `limits`.
LoadResult load_collada_file(const std::filesystem::path& path, const LoadLimits& limits = {});

/// Same, from memory; `label` names the source in messages.
LoadResult load_collada_string(std::string_view xml, const std::string& label, const LoadLimits& limits = {});

/// One line: triangles, spheres, lights by type, bounds, load time.
std::string scene_summary(const LoadResult& r);

/// The --scene-info report: the summary, the contents and the warnings
/// (what was ignored), one item a line.
std::string scene_info(const LoadResult& r);

}  // namespace pt
