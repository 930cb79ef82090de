// POST /api/nav, /api/settings and /api/camera: the shared view's changes.
#include <cmath>

#include "request_params.h"
#include "route_support.h"

namespace pt::live {
namespace {

constexpr double kMaxPixels = 1e5;       ///< the largest move one request makes, in pixels
constexpr double kMaxZoomSteps = 100;    ///< 1.1^100: 13780 times nearer or farther
constexpr float kMaxCoordinate = 1e15f;  ///< the scene loader's coordinate limit
constexpr std::array<const char*, 5> kNavOps = {"orbit", "pan", "zoom", "reset", "still"};  // NavInput::Kind

void navigate(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"op", "dx", "dy", "steps", "moving"});
  NavInput in;
  in.kind = static_cast<NavInput::Kind>(params.choice("op", kNavOps));
  in.moving = params.has("moving") && params.integer("moving", 0, 1) == 1;
  if (in.kind == NavInput::Kind::kOrbit || in.kind == NavInput::Kind::kPan) {
    if (params.has("steps")) throw ParamError("steps: only op=zoom takes it");
    in.dx = params.number("dx", -kMaxPixels, kMaxPixels);
    in.dy = params.number("dy", -kMaxPixels, kMaxPixels);
  } else if (in.kind == NavInput::Kind::kZoom) {
    if (params.has("dx") || params.has("dy")) throw ParamError("dx, dy: op=zoom takes steps");
    in.dx = params.number("steps", -kMaxZoomSteps, kMaxZoomSteps);
  } else if (params.has("dx") || params.has("dy") || params.has("steps")) {
    throw ParamError("op=" + std::string(kNavOps[size_t(in.kind)]) + " takes no dx, dy or steps");
  }
  reply_json(res, {{"version", ctx.session.navigate(in)}});
}

void change_settings(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"width", "height", "samples", "light", "depth", "display", "bounces", "direct",
                                    "adaptive_tolerance", "adaptive_batch", "preview"});
  ViewSettings s = ctx.session.view().settings;
  if (params.has("width")) s.width = int(params.integer("width", kMinViewSide, kMaxViewSide));
  if (params.has("height")) s.height = int(params.integer("height", kMinViewSide, kMaxViewSide));
  if (params.has("samples")) s.samples = int(params.integer("samples", 1, 1 << 24));
  if (params.has("light")) s.light_samples = int(params.integer("light", 1, 4096));
  if (params.has("depth")) s.max_depth = int(params.integer("depth", 0, 1024));
  if (params.has("adaptive_batch")) s.adaptive_batch = int(params.integer("adaptive_batch", 1, 1 << 24));
  if (params.has("adaptive_tolerance")) s.adaptive_tolerance = float(params.number("adaptive_tolerance", 0, 1e30));
  if (params.has("preview")) {
    int p = int(params.integer("preview", 0, 8));
    if (p != 0 && p != 1 && p != 2 && p != 4 && p != 8)
      throw ParamError("preview: must be 0 (automatic), 1, 2, 4 or 8");
    s.preview = uint8_t(p);
  }
  if (params.has("display")) s.display = static_cast<Display>(params.choice("display", kDisplayNames));
  if (params.has("bounces")) s.bounces = static_cast<BounceMode>(params.choice("bounces", kBounceNames));
  if (params.has("direct")) s.direct = static_cast<DirectLighting>(params.choice("direct", kDirectNames));
  if (std::string problem = view_settings_problem(s); !problem.empty()) throw ParamError(problem);
  uint64_t version = ctx.session.set_settings(s);
  reply_json(res, {{"version", version}, {"settings", settings_json(s)}});
}

/// Places the camera at `position` looking at `target`, optionally with a vertical field of view.
void set_camera(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"position", "target", "vfov"});
  const float3 position = params.vector("position", kMaxCoordinate);
  const float3 target = params.vector("target", kMaxCoordinate);
  const NavLimits& limits = ctx.session.config().limits;
  if (std::string problem = look_at_problem(position, target, limits); !problem.empty()) throw ParamError(problem);
  RenderSession::View v = ctx.session.view();
  ViewCamera c = look_at(v.camera, position, target, limits);
  if (params.has("vfov")) {
    double vfov = params.number("vfov", 0.1, 179.0);
    double half = std::tan(vfov * M_PI / 360.0) * v.settings.width / v.settings.height;
    c.vfov_deg = float(vfov);
    c.hfov_deg = float(std::min(179.0, 2.0 * std::atan(half) * 180.0 / M_PI));
  }
  if (std::string problem = camera_settings_problem(c); !problem.empty()) throw ParamError("camera: " + problem);
  reply_json(res, {{"version", ctx.session.set_camera(c)}, {"camera", camera_json(c)}});
}

}  // namespace

void add_view_routes(HttpServer& server, RouteContext& ctx) {
  server.post("/api/nav", guarded([&ctx](const Request& q, Response& r) { navigate(ctx, q, r); }));
  server.post("/api/settings", guarded([&ctx](const Request& q, Response& r) { change_settings(ctx, q, r); }));
  server.post("/api/camera", guarded([&ctx](const Request& q, Response& r) { set_camera(ctx, q, r); }));
}

}  // namespace pt::live
