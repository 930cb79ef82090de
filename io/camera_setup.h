// Resolves a scene's camera for one output size, the course renderer's way:
// the camera looks at the centre of the scene's bounds from
// centre + 1.5 |diagonal| d, +Y up, and the fields of view are widened to the
// image's aspect. A camera settings file (-c) replaces all of that.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "kernels/scene/camera.h"
#include "kernels/scene/scene.h"

namespace pt {

/// Contents of a CS184 camera settings file (docs/flags.md, -c).
struct CameraSettingsFile {
  float hfov_deg = 0, vfov_deg = 0, aspect = 0, near_clip = 0, far_clip = 0;
  float3 position, target;
  float phi = 0, theta = 0, r = 0, min_r = 0, max_r = 0;
  float c2w[3][3] = {};  ///< row-major; columns are screen x, screen y, to-camera
  float screen_w = 0, screen_h = 0, screen_dist = 0;
  float focal_distance = 0, lens_radius = 0;
};

/// Throws InputError naming the file and the field that does not parse.
CameraSettingsFile read_camera_settings_file(const std::filesystem::path& path);

/// What makes `f` unusable as a camera (fields of view outside (0, 180),
/// clip range, lens, c2w columns not unit), or "" when it is usable: the
/// checks read_camera_settings_file applies after parsing.
std::string camera_settings_problem(const CameraSettingsFile& f);

/// The file's fields of the camera of a render at width x height.
CameraSettingsFile camera_settings_of(const Camera& c, int width, int height);

/// The file's text: every field with 9 significant digits, so that each
/// float reads back bit for bit (and resolve_camera gives the same camera).
std::string format_camera_settings(const CameraSettingsFile& f);

/// Writes the camera of a render so that -c reproduces it.
void write_camera_settings_file(const std::filesystem::path& path, const Camera& c, int width, int height);
void write_camera_settings_file(const std::filesystem::path& path, const CameraSettingsFile& f);

/// `cs184_framing`: keep the course renderer's pixel scale of an 800x600 view
/// (the output is then the central crop of that view).
Camera resolve_camera(const Scene& scene, int width, int height, bool cs184_framing = false);
Camera resolve_camera(const CameraSettingsFile& file, int width, int height);

}  // namespace pt
