// Camera navigation of the live view, the course renderer's way: the camera
// orbits a target on a sphere (phi measured from +Y, theta about +Y, radius
// r), pans by moving camera and target in the screen plane, and zooms by
// scaling r. The state is the camera file's fields (io/camera_setup.h), so
// the camera on screen and the one a saved file gives -c are one camera:
// resolve_camera(view, width, height) renders both.
#pragma once

#include <string>

#include "io/camera_setup.h"
#include "kernels/math/bbox.h"
#include "kernels/scene/camera.h"

namespace pt::live {

/// The live view's camera: the fields `pathtracer -c` reads.
using ViewCamera = CameraSettingsFile;

/// 24 bytes. How near and how far the camera may zoom to its target, and how far a pan or a placed
/// camera may take the target from the scene's centre (beyond that, floats lose the view's detail).
struct NavLimits {
  float min_r = 1e-3f, max_r = 1e3f;
  float3 centre{};
  float reach = 1e3f;
};
static_assert(sizeof(NavLimits) == 24);

/// 1e-3 and 100 times the diagonal of the scene's bounds (1 for an empty scene) from its centre, and a reach
/// of 100 diagonals.
NavLimits nav_limits(const BBox& scene_bounds);

/// The view of a resolved camera at width x height, orbiting the point of its
/// view axis nearest to `centre` (at least min_r ahead); its basis is kept
/// until the first orbit rebuilds it.
ViewCamera view_from_camera(const Camera& c, int width, int height, float3 centre, const NavLimits& limits);

/// Turns the camera about its target by dragged pixels, as the course's
/// window does: phi -= dy * pi / height, theta -= dx * pi / width; phi stays
/// inside (0, pi) and the basis is rebuilt with +Y up.
ViewCamera orbit(const ViewCamera& v, double dx, double dy, int width, int height);

/// Moves camera and target in the screen plane so that a point at the
/// target's depth follows the mouse: `tan_half_vfov` is the resolved camera's
/// and `height` the view's, in pixels (dy grows downwards). A move that would
/// take the target beyond the limits' reach stops at it.
ViewCamera pan(const ViewCamera& v, double dx, double dy, float tan_half_vfov, int height, const NavLimits& limits);

/// Scales the distance to the target by 1.1^steps within the limits.
ViewCamera zoom(const ViewCamera& v, double steps, const NavLimits& limits);

/// The camera at `position` looking at `target` with +Y up (the course's
/// basis), fields of view and lens from `v`. `position` must differ from `target`;
/// a distance or direction that look_at_problem refuses is clamped.
ViewCamera look_at(const ViewCamera& v, float3 position, float3 target, const NavLimits& limits);

/// Why look_at cannot place the camera at `position` exactly (closer than
/// min_r or farther than max_r from `target`, a target beyond the reach of
/// the scene's centre, or straight above or below it, where the +Y basis
/// degenerates), or "".
std::string look_at_problem(float3 position, float3 target, const NavLimits& limits);

/// `v` with the file's screen fields (aspect, screen_w, screen_h, screen_dist)
/// of a width x height view; the camera it resolves to at that size is unchanged.
ViewCamera fit_screen(const ViewCamera& v, int width, int height);

/// Where world point `p` lands in a width x height view of `c`, in pixels
/// from the top-left corner (x right, y down); false when it lies behind the
/// camera's plane. The overlays' projection (the page computes the same).
bool project_to_pixel(const Camera& c, int width, int height, float3 p, float& px, float& py);

}  // namespace pt::live
