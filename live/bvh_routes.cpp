// GET /api/bvh/level and /api/bvh/walk: the BVH overlays' boxes, in world
// coordinates (the page projects them with the frame's camera).
#include "bvh/bvh4_inspect.h"
#include "io/camera_setup.h"
#include "kernels/simd/isa.h"
#include "request_params.h"
#include "route_support.h"

namespace pt::live {
namespace {

constexpr size_t kMaxBoxes = 4096;
constexpr size_t kMaxVisits = 4096;

nlohmann::json box_json(const BBox& b) {
  return nlohmann::json::array({b.lower.x, b.lower.y, b.lower.z, b.upper.x, b.upper.y, b.upper.z});
}

void level(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"depth"});
  const int depth = int(params.integer("depth", 0, 64));
  Bvh4Level l = bvh4_level(ctx.bvh.bvh(), depth, kMaxBoxes);
  nlohmann::json boxes = nlohmann::json::array();
  for (const BBox& b : l.boxes) boxes.push_back(box_json(b));
  reply_json(
      res,
      {{"depth", depth}, {"max_depth", ctx.bvh_max_depth}, {"boxes", std::move(boxes)}, {"truncated", l.truncated}});
}

/// The walk of the camera ray through point (x, y) of the view (pixels from
/// the top-left corner; a pixel's centre is at + 0.5), through the lens centre.
void walk(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"x", "y"});
  RenderSession::View v = ctx.session.view();
  const double x = params.number("x", 0, v.settings.width), y = params.number("y", 0, v.settings.height);
  const Camera c = resolve_camera(v.camera, v.settings.width, v.settings.height);
  const Ray ray = camera_ray(c, float(x / v.settings.width), float(1.0 - y / v.settings.height));
  Bvh4Walk w = walk_bvh4(ctx.bvh, ray, kMaxVisits);
  nlohmann::json visits = nlohmann::json::array();
  for (const Bvh4Visit& s : w.visits)
    visits.push_back({{"box", box_json(s.box)}, {"depth", s.depth}, {"leaf", s.leaf != 0}});
  nlohmann::json hit = nullptr;
  if (w.hit.valid()) {
    float3 p = ray.org + ray.dir * w.hit.t;
    hit = {{"t", w.hit.t}, {"prim", w.hit.prim}, {"point", {p.x, p.y, p.z}}};
  }
  reply_json(res, {{"x", x},
                   {"y", y},
                   {"version", v.version},
                   {"inner_nodes", w.inner_nodes},
                   {"leaves", w.leaves},
                   {"hit", hit},
                   {"visits", std::move(visits)},
                   {"truncated", w.inner_nodes + w.leaves > w.visits.size()}});
}

}  // namespace

void add_bvh_routes(HttpServer& server, RouteContext& ctx) {
  server.get("/api/bvh/level", guarded([&ctx](const Request& q, Response& r) { level(ctx, q, r); }));
  server.get("/api/bvh/walk", guarded([&ctx](const Request& q, Response& r) { walk(ctx, q, r); }));
}

}  // namespace pt::live
