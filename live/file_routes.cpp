// POST /api/camera/save, /api/render and /api/render/cancel: the only
// requests that write files. They write to a fixed path chosen on the
// command line, or to a name the request gives, which must be a plain file
// name (request_params.h) and lands in the start directory; writes are atomic.
#include "io/atomic_file.h"
#include "request_params.h"
#include "route_support.h"

namespace pt::live {
namespace {

std::filesystem::path target(const RouteContext& ctx, const RequestParams& params, const char* extension,
                             const std::filesystem::path& fixed) {
  return params.has("name") ? ctx.config.directory / params.file_name("name", extension) : fixed;
}

void save_camera(RouteContext& ctx, const httplib::Request& req, httplib::Response& res) {
  RequestParams params(req.params, {"name"});
  std::filesystem::path path = target(ctx, params, ".txt", ctx.config.camera_file);
  RenderSession::View v = ctx.session.view();
  write_camera_settings_file(path, v.camera);
  reply_json(res, {{"file", path.string()}, {"version", v.version}, {"camera", camera_json(v.camera)}});
}

void start_render(RouteContext& ctx, const httplib::Request& req, httplib::Response& res) {
  RequestParams params(req.params, {"name"});
  std::filesystem::path path = target(ctx, params, ".png", ctx.config.image_file);
  check_writable(path);
  if (std::string why = ctx.session.start_job(path); !why.empty()) return reply_error(res, 409, why);
  reply_json(res, {{"file", path.string()}, {"state", "rendering"}}, 202);
}

}  // namespace

void add_file_routes(httplib::Server& server, RouteContext& ctx) {
  server.Post("/api/camera/save",
              guarded([&ctx](const httplib::Request& q, httplib::Response& r) { save_camera(ctx, q, r); }));
  server.Post("/api/render",
              guarded([&ctx](const httplib::Request& q, httplib::Response& r) { start_render(ctx, q, r); }));
  server.Post("/api/render/cancel", guarded([&ctx](const httplib::Request& q, httplib::Response& r) {
                RequestParams params(q.params, {});
                reply_json(r, {{"cancelled", ctx.session.cancel_job()}});
              }));
}

}  // namespace pt::live
