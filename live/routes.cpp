// The guard, the embedded assets, /api/state and /api/frame; the other
// routes are in view_routes.cpp, file_routes.cpp and bvh_routes.cpp.
#include "routes.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <memory>
#include <regex>

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

void reply_json(httplib::Response& res, const nlohmann::json& body, int status) {
  res.status = status;
  res.set_content(json_text(body), "application/json");
}

void reply_error(httplib::Response& res, int status, const std::string& message) {
  std::string line = log_safe(message, 300);
  res.set_header("X-PT-Error", line);
  reply_json(res, {{"error", line}}, status);
}

Handler guarded(Handler handler) {
  return [handler = std::move(handler)](const httplib::Request& req, httplib::Response& res) {
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

/// Host must be one of `hosts` (in any case) and a POST must carry X-PT-Live.
httplib::Server::HandlerResponse guard(const RouteContext& ctx, const httplib::Request& req, httplib::Response& res) {
  auto refuse = [&res](int status, const std::string& why) {
    reply_error(res, status, why);
    res.set_header("Connection", "close");  // a body the request may carry is left unread
    return httplib::Server::HandlerResponse::Handled;
  };
  const auto& hosts = ctx.config.hosts;
  const std::string host = req.get_header_value("Host");
  std::string lower = host;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (std::find(hosts.begin(), hosts.end(), lower) == hosts.end())
    return refuse(403, "Host \"" + host + "\" is not this server's address");
  if (req.method != "GET" && req.method != "HEAD" && req.method != "POST")
    return refuse(405, "method " + req.method + " is not used here");
  if (req.method == "POST" && req.get_header_value("X-PT-Live") != "1")
    return refuse(403, "a POST needs the header X-PT-Live: 1 (the page sends it)");
  return httplib::Server::HandlerResponse::Unhandled;
}

std::string escape_regex(std::string_view path) {
  std::string out;
  for (char c : path) {
    if (std::strchr(".^$|()[]{}*+?\\", c)) out += '\\';
    out += c;
  }
  return out;
}

void add_state_routes(httplib::Server& server, RouteContext& ctx) {
  server.Get("/api/state", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
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
                           {"frame_waits", ctx.shares.frame_waits()}}},
                         {"names", {{"display", kDisplayNames}, {"bounces", kBounceNames}, {"direct", kDirectNames}}}});
             }));
  server.Get("/api/render", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               RequestParams params(req.params, {});
               reply_json(res, job_json(ctx.session.job()));
             }));
}

/// GET /api/frame?after=N: the newest frame once newer than N, as
/// [u32 little-endian length of the JSON][the JSON][width * height * 4 RGBA bytes]; 204 after the wait;
/// 429 when the client has its share of frame requests waiting already; 500 when the view's render failed;
/// 503 once the server stops (the page then waits before asking again).
void add_frame_route(httplib::Server& server, RouteContext& ctx) {
  server.Get("/api/frame", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               RequestParams params(req.params, {"after"});
               uint64_t after = params.has("after") ? uint64_t(params.integer("after", 0, int64_t(1) << 53)) : 0;
               FrameWait wait(ctx.shares, client_of(req.remote_addr));
               if (!wait)
                 return reply_error(res, 429,
                                    "this client has " + std::to_string(ctx.shares.limits().frame_waits_per_client) +
                                        " frame requests waiting already");
               std::shared_ptr<const Frame> frame = ctx.session.frame_after(after, ctx.config.frame_wait);
               if (ctx.session.stopped()) {
                 res.set_header("Connection", "close");
                 return reply_error(res, 503, "the server is stopping");
               }
               if (!frame) {
                 if (std::string why = ctx.session.render_error(); !why.empty())
                   return reply_error(res, 500, "the render of this view failed: " + why);
                 res.status = 204;
                 return;
               }
               auto head = std::make_shared<std::string>(4, '\0');
               const std::string meta = json_text(frame_json(frame->info, ctx.session.view().settings_version));
               const uint32_t n = uint32_t(meta.size());
               for (int i = 0; i < 4; ++i) (*head)[i] = char((n >> (8 * i)) & 0xff);
               *head += meta;
               // The pixels are sent from the frame itself, not copied into the response.
               const std::string& rgba = frame->rgba();
               res.set_content_provider(
                   head->size() + rgba.size(), "application/octet-stream",
                   [head, frame](size_t offset, size_t length, httplib::DataSink& sink) {
                     const std::string& pixels = frame->rgba();
                     while (length > 0) {
                       const bool in_head = offset < head->size();
                       const char* from = in_head ? head->data() + offset : pixels.data() + (offset - head->size());
                       const size_t part =
                           std::min(length, in_head ? head->size() - offset : pixels.size() - (offset - head->size()));
                       if (!sink.write(from, part)) return false;
                       offset += part;
                       length -= part;
                     }
                     return true;
                   });
             }));
}

}  // namespace

void add_routes(HttpServer& server, RenderSession& session, const SceneBvh4& bvh, const RouteConfig& config) {
  auto ctx =
      std::make_shared<RouteContext>(RouteContext{session, bvh, server.shares(), config, bvh4_max_depth(bvh.bvh())});
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"},
                              {"X-Frame-Options", "DENY"},
                              {"Referrer-Policy", "no-referrer"},
                              {"Cache-Control", "no-store"},
                              {"Content-Security-Policy",
                               "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
                               "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'"}});
  // The guard holds the context; the routes below use it by reference for as long as the server holds the guard.
  server.set_request_guard(
      [ctx](const httplib::Request& req, httplib::Response& res) { return guard(*ctx, req, res); });
  server.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "internal error";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) { what = e.what(); } catch (...) {
    }
    reply_error(res, 500, what);
  });
  for (const Asset& a : embedded_assets())
    server.Get(escape_regex(a.path), [a](const httplib::Request& req, httplib::Response& res) {
      if (!req.params.empty()) return reply_error(res, 400, "the page takes no parameters");
      res.set_content(a.bytes.data(), a.bytes.size(), std::string(a.content_type));
    });
  add_state_routes(server, *ctx);
  add_frame_route(server, *ctx);
  add_view_routes(server, *ctx);
  add_file_routes(server, *ctx);
  add_bvh_routes(server, *ctx);
}

}  // namespace pt::live
