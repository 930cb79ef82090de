// The live view's start: scene, environment map and warnings as for a
// render; the view's camera and settings from the flags; the files the page
// writes by default: -f's image (else <scene>.png) and --write-camera's file
// (else <scene>_camera.txt) in the start directory.
#include "live_command.h"

#include <cstdio>
#include <filesystem>
#include <memory>

#include "io/camera_setup.h"
#include "io/collada_loader.h"
#include "io/exr_image.h"
#include "live/live_view.h"
#include "render_camera.h"
#include "render_outputs.h"

namespace pt::cli {

int run_live_view(const Options& o, const std::atomic<bool>& stop) {
  std::filesystem::path scene_path =
      o.scene_path.empty() ? std::filesystem::path(PT_DEFAULT_SCENE) : std::filesystem::path(o.scene_path);
  LoadResult loaded = load_collada_file(scene_path);
  for (const std::string& w : loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!o.environment_map.empty()) {
    RgbImage map = read_exr(o.environment_map);
    set_environment(loaded.scene, std::make_shared<EnvironmentMap>(map.width, map.height, std::move(map.texels)));
  }
  const Scene& scene = loaded.scene;
  const RenderSettings& rs = o.settings;
  if (!o.quiet) std::printf("%s\n", scene_summary(loaded).c_str());

  live::LiveOptions lo;
  lo.bind = o.bind_address;
  lo.port = o.serve_port;
  lo.directory = std::filesystem::current_path();
  const std::string stem = std::filesystem::path(scene.name).stem().string();
  lo.image_file = o.output_path.empty() ? lo.directory / (stem + ".png") : std::filesystem::path(o.output_path);
  lo.camera_file =
      o.write_camera_file.empty() ? lo.directory / (stem + "_camera.txt") : std::filesystem::path(o.write_camera_file);
  lo.quiet = o.quiet;
  live::SessionConfig& sc = lo.session;
  sc.base = rs;
  sc.settings = live::view_settings_of(rs);
  sc.limits = live::nav_limits(scene.bounds);
  const Camera camera = render_camera(o, scene);
  const float3 centre = scene.bounds.empty() ? camera.position - camera.to_camera : scene.bounds.center();
  sc.camera = live::view_from_camera(camera, rs.width, rs.height, centre, sc.limits);
  sc.quantization = png_quantization(o);
  return live::serve_live_view(scene, lo, stop);
}

}  // namespace pt::cli
