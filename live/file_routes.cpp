// POST /api/camera/save, /api/render and /api/render/cancel: the only
// requests that write files. They write to a fixed path chosen on the
// command line (replaced each time), or to a name the request gives, which
// must be a plain file name (request_params.h), lands in the start directory
// and never replaces a file: a name in use is answered 409. Files appear
// whole (written aside, then renamed or linked into place), and a reply that
// reports a file is made before the file is put in place: a request that
// fails leaves no file.
#include "io/atomic_file.h"
#include "io/camera_setup.h"
#include "io/image_output.h"
#include "request_params.h"
#include "route_support.h"

namespace pt::live {
namespace {

std::filesystem::path target(const RouteContext& ctx, const RequestParams& params, const char* extension,
                             const std::filesystem::path& fixed) {
  return params.has("name") ? ctx.config.directory / params.file_name("name", extension) : fixed;
}

/// Whether anything (a file, a directory, a dangling link) has this name.
bool taken(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::symlink_status(path, ec).type() != std::filesystem::file_type::not_found;
}

void refuse_taken(Response& res, const std::filesystem::path& path) {
  reply_error(res, 409, path.filename().string() + " exists in the start directory: choose another name");
}

void save_camera(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"name"});
  std::filesystem::path path = target(ctx, params, ".txt", ctx.config.camera_file);
  RenderSession::View v = ctx.session.view();
  // The screen fields of the view's size now (the camera it resolves to is the view's either way).
  const ViewCamera camera = fit_screen(v.camera, v.settings.width, v.settings.height);
  std::string reply = json_text({{"file", path.string()}, {"version", v.version}, {"camera", camera_json(camera)}});
  if (!StagedFile(path, format_camera_settings(camera)).publish(!params.has("name"))) return refuse_taken(res, path);
  res.set_content(std::move(reply), "application/json");
}

void start_render(RouteContext& ctx, const Request& req, Response& res) {
  RequestParams params(req.params, {"name"});
  const bool named = params.has("name");
  std::filesystem::path path = target(ctx, params, ".png", ctx.config.image_file);
  const bool adaptive = render_settings(ctx.session.config().base, ctx.session.view().settings, 1, 1).adaptive();
  if (named && taken(path)) return refuse_taken(res, path);
  if (named && adaptive && taken(rate_image_path(path))) return refuse_taken(res, rate_image_path(path));
  check_writable(path);
  std::string reply = json_text({{"file", path.string()}, {"state", "rendering"}});
  if (std::string why = ctx.session.start_job(path, !named); !why.empty()) return reply_error(res, 409, why);
  res.status = 202;
  res.set_content(std::move(reply), "application/json");
}

}  // namespace

void add_file_routes(HttpServer& server, RouteContext& ctx) {
  server.post("/api/camera/save", guarded([&ctx](const Request& q, Response& r) { save_camera(ctx, q, r); }));
  server.post("/api/render", guarded([&ctx](const Request& q, Response& r) { start_render(ctx, q, r); }));
  server.post("/api/render/cancel", guarded([&ctx](const Request& q, Response& r) {
                RequestParams params(q.params, {});
                reply_json(r, {{"cancelled", ctx.session.cancel_job()}});
              }));
}

}  // namespace pt::live
