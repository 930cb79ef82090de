// The guard, the embedded assets, /api/state and /api/frame; the other
// routes are in view_routes.cpp, file_routes.cpp and bvh_routes.cpp.
#include "routes.h"

#include <algorithm>
#include <cctype>
#include <memory>

#include "assets.h"
#include "bvh/bvh4_inspect.h"
#include "io/scene_error.h"
#include "kernels/simd/isa.h"
#include "request_params.h"
#include "route_support.h"

namespace pt::live {

std::string json_text(const nlohmann::json& body) {
  return body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void reply_json(Response& res, const nlohmann::json& body, int status) {
  res.status = status;
  res.set_content(json_text(body), "application/json");
}

void reply_error(Response& res, int status, const std::string& message) {
  std::string line = log_safe(message, 300);
  res.set_header("X-PT-Error", line);
  reply_json(res, {{"error", line}}, status);
}

Handler guarded(Handler handler) {
  return [handler = std::move(handler)](const Request& req, Response& res) {
    try {
      handler(req, res);
    } catch (const ParamError& e) { reply_error(res, 400, e.what()); } catch (const InputError& e) {
      reply_error(res, 500, e.what());
    }
  };
}

nlohmann::json camera_json(const ViewCamera& c) {
  auto v = [](float3 p) { return nlohmann::json::array({p.x, p.y, p.z}); };
  nlohmann::json c2w = nlohmann::json::array();
  for (const auto& row : c.c2w) c2w.push_back({row[0], row[1], row[2]});
  return {{"hfov", c.hfov_deg},
          {"vfov", c.vfov_deg},
          {"near", c.near_clip},
          {"far", c.far_clip},
          {"position", v(c.position)},
          {"target", v(c.target)},
          {"phi", c.phi},
          {"theta", c.theta},
          {"r", c.r},
          {"c2w", c2w},
          {"focal_distance", c.focal_distance},
          {"lens_radius", c.lens_radius}};
}

nlohmann::json settings_json(const ViewSettings& s) {
  return {{"width", s.width},
          {"height", s.height},
          {"samples", s.samples},
          {"light", s.light_samples},
          {"depth", s.max_depth},
          {"adaptive_tolerance", s.adaptive_tolerance},
          {"adaptive_batch", s.adaptive_batch},
          {"display", kDisplayNames[size_t(s.display)]},
          {"bounces", kBounceNames[size_t(s.bounces)]},
          {"direct", kDirectNames[size_t(s.direct)]},
          {"preview", s.preview}};
}

namespace {

/// The frame's description for the page's overlay and overlays.
nlohmann::json frame_json(const FrameInfo& f, uint64_t settings_version) {
  auto v = [](float3 p) { return nlohmann::json::array({p.x, p.y, p.z}); };
  const Camera& c = f.camera;
  return {{"id", f.id},
          {"version", f.view_version},
          {"settings_version", settings_version},
          {"width", f.width},
          {"height", f.height},
          {"view_width", f.view_width},
          {"view_height", f.view_height},
          {"samples", f.samples},
          {"target", f.target},
          {"complete", f.complete},
          {"seconds", f.seconds},
          {"render_seconds", f.render_seconds},
          {"rays", f.rays},
          {"mrays", f.render_seconds > 0 ? double(f.rays) / f.render_seconds / 1e6 : 0.0},
          {"estimated_relative_rmse",
           f.estimated_relative_rmse >= 0 ? nlohmann::json(f.estimated_relative_rmse) : nlohmann::json(nullptr)},
          {"display", kDisplayNames[size_t(f.display)]},
          {"camera",
           {{"position", v(c.position)},
            {"screen_x", v(c.screen_x)},
            {"screen_y", v(c.screen_y)},
            {"to_camera", v(c.to_camera)},
            {"tan_half_hfov", c.tan_half_hfov},
            {"tan_half_vfov", c.tan_half_vfov}}}};
}

nlohmann::json job_json(const RenderJob& j) {
  return {{"state", kJobStateNames[size_t(j.state)]},
          {"file", j.path.string()},
          {"progress", j.progress},
          {"message", j.message}};
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Host must be one of `hosts` (in any case) and the method GET, HEAD or POST. An API request must come from
/// the page: it carries X-PT-Live: 1 (another site's page cannot send it: that takes a CORS preflight, which
/// the server never grants), and no Origin or Sec-Fetch-Site that names another site.
void guard(const RouteContext& ctx, const Request& req, Response& res) {
  const auto ours = [&ctx](const std::string& host) {
    return std::find(ctx.config.hosts.begin(), ctx.config.hosts.end(), lower(host)) != ctx.config.hosts.end();
  };
  const std::string host = req.header("Host"), origin = req.header("Origin"), site = req.header("Sec-Fetch-Site");
  if (!ours(host)) return reply_error(res, 403, "Host \"" + host + "\" is not this server's address");
  if (req.method != "GET" && req.method != "HEAD" && req.method != "POST")
    return reply_error(res, 405, "method " + req.method + " is not used here");
  if (req.path.rfind("/api/", 0) != 0) return;
  if (req.header("X-PT-Live") != "1")
    return reply_error(res, 403, "an API request needs the header X-PT-Live: 1 (the page sends it)");
  if (req.header_count("Origin") && !(origin.rfind("http://", 0) == 0 && ours(origin.substr(7))))
    return reply_error(res, 403, "Origin \"" + origin + "\" is another site");
  if (req.header_count("Sec-Fetch-Site") && site != "same-origin")
    return reply_error(res, 403, "Sec-Fetch-Site \"" + site + "\": the request comes from another site");
}

void add_state_routes(HttpServer& server, RouteContext& ctx) {
  server.get("/api/state", guarded([&ctx](const Request& req, Response& res) {
               RequestParams params(req.params, {});
               RenderSession::View v = ctx.session.view();
               SessionCounters n = ctx.session.counters();
               const Isa isa = ctx.bvh.isa();
               reply_json(
                   res, {{"scene", ctx.config.scene_name},
                         {"triangles", ctx.bvh.stats().triangles},
                         {"isa", std::string(isa_name(isa))},
                         {"lanes", isa_lanes(isa)},
                         {"threads", ctx.session.config().base.threads},
                         {"camera", camera_json(v.camera)},
                         {"settings", settings_json(v.settings)},
                         {"version", v.version},
                         {"settings_version", v.settings_version},
                         {"job", job_json(ctx.session.job())},
                         {"render_error", ctx.session.render_error()},
                         {"counters",
                          {{"frames", n.frames},
                           {"passes_cancelled", n.passes_cancelled},
                           {"max_chunks_after_cancel", n.max_chunks_after_cancel},
                           {"last_cancel_seconds", n.last_cancel_seconds},
                           {"connections", ctx.shares.open()},
                           {"frame_waits", ctx.shares.frame_waits()},
                           {"frame_bytes_sent", ctx.frames.bytes()}}},
                         {"names", {{"display", kDisplayNames}, {"bounces", kBounceNames}, {"direct", kDirectNames}}}});
             }));
  server.get("/api/render", guarded([&ctx](const Request& req, Response& res) {
               RequestParams params(req.params, {});
               reply_json(res, job_json(ctx.session.job()));
             }));
}

/// What a frame response sends and holds until it is sent.
struct FrameBody {
  std::string head;  ///< the length of the JSON and the JSON
  std::shared_ptr<const Frame> frame;
  std::unique_ptr<FramesInFlight::Lease> lease;
};

/// The reply to a frame request once its wait is over: the newest frame after `after`, or 204, 500 or 503.
void reply_frame(RouteContext& ctx, uint64_t after, uint64_t connection, Response& res) {
  std::shared_ptr<const Frame> frame = ctx.session.frame_after(after, std::chrono::milliseconds(0));
  if (ctx.session.stopped()) return reply_error(res, 503, "the server is stopping");
  if (!frame) {
    if (std::string why = ctx.session.render_error(); !why.empty())
      return reply_error(res, 500, "the render of this view failed: " + why);
    res.status = 204;
    return;
  }
  auto body = std::make_shared<FrameBody>();
  const std::string meta = json_text(frame_json(frame->info, ctx.session.view().settings_version));
  for (int i = 0; i < 4; ++i) body->head += char((meta.size() >> (8 * i)) & 0xff);
  body->head += meta;
  // The pixels are sent from the frame itself, not copied; a frame being sent counts against the budget.
  const std::string& rgba = frame->rgba();
  FramesInFlight::Leased leased = ctx.frames.lease(frame->info.id, body->head.size() + rgba.size(), connection);
  for (uint64_t cut : leased.cut)
    if (ctx.shares.end(cut))
      ctx.log("live: cut a connection sending an older frame: the frames being sent would hold more than " +
              std::to_string(ctx.config.frame_bytes >> 20) + " MiB");
  body->frame = std::move(frame);
  body->lease = std::move(leased.lease);
  res.content_type = "application/octet-stream";
  res.parts = {body->head, rgba};
  res.keep = std::move(body);
}

/// GET /api/frame?after=N: the newest frame once newer than N, as
/// [u32 little-endian length of the JSON][the JSON][width * height * 4 RGBA bytes]; 204 after the wait;
/// 429 when the client has its share of frame requests waiting already; 500 when the view's render failed;
/// 503 once the server stops (the page then waits before asking again). The wait holds no thread.
void add_frame_route(HttpServer& server, RouteContext& ctx) {
  server.get("/api/frame", guarded([&ctx](const Request& req, Response& res) {
               RequestParams params(req.params, {"after"});
               uint64_t after = params.has("after") ? uint64_t(params.integer("after", 0, int64_t(1) << 53)) : 0;
               auto wait = std::make_shared<FrameWait>(ctx.shares, client_of(req.remote_addr));
               if (!*wait)
                 return reply_error(res, 429,
                                    "this client has " + std::to_string(ctx.shares.limits().frame_waits_per_client) +
                                        " frame requests waiting already");
               auto ready = [&ctx, after] {
                 return ctx.session.stopped() || !ctx.session.render_error().empty() ||
                        ctx.session.frame_after(after, std::chrono::milliseconds(0));
               };
               auto reply = [&ctx, after, wait, connection = req.connection](Response& r) {
                 reply_frame(ctx, after, connection, r);
               };
               res.deferred = std::make_shared<Response::Wait>(Response::Wait{ready, ctx.config.frame_wait, reply});
             }));
}

}  // namespace

void add_routes(HttpServer& server, RenderSession& session, const SceneBvh4& bvh, const RouteConfig& config) {
  auto ctx = std::make_shared<RouteContext>(session, bvh, server.shares(), config, bvh4_max_depth(bvh.bvh()));
  ctx->log = [&server](const std::string& line) { server.log(line); };
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"X-Frame-Options", "DENY"},
                              {"Referrer-Policy", "no-referrer"},
                              {"Cache-Control", "no-store"},
                              {"Content-Security-Policy",
                               "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
                               "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'"}});
  // The guard holds the context; the routes below use it by reference for as long as the server holds the guard.
  server.set_guard([ctx](const Request& req, Response& res) { guard(*ctx, req, res); });
  for (const Asset& a : embedded_assets())
    server.get(std::string(a.path), [a](const Request& req, Response& res) {
      if (!req.params.empty()) return reply_error(res, 400, "the page takes no parameters");
      res.content_type = std::string(a.content_type);
      res.parts = {a.bytes};  // sent from the binary's own bytes
    });
  add_state_routes(server, *ctx);
  add_frame_route(server, *ctx);
  add_view_routes(server, *ctx);
  add_file_routes(server, *ctx);
  add_bvh_routes(server, *ctx);
}

}  // namespace pt::live
