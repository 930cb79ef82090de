// What the route files share: the context every handler sees, JSON and
// error replies (an error is a status, a one-line X-PT-Error header the log
// repeats, and {"error": ...}), and the wrapper that turns a bad parameter
// into 400 and a failed write into 500. Every JSON reply survives any name:
// bytes that are not UTF-8 are replaced (json_text).
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "bvh/scene_bvh4.h"
#include "frames_in_flight.h"
#include "render_session.h"
#include "routes.h"

namespace pt::live {

struct RouteContext {
  RouteContext(RenderSession& s, const SceneBvh4& b, ClientShares& sh, const RouteConfig& c, int depth)
      : session(s), bvh(b), shares(sh), config(c), bvh_max_depth(depth), frames(c.frame_bytes) {}
  RenderSession& session;
  const SceneBvh4& bvh;
  ClientShares& shares;  ///< the server's: frame requests wait within their client's share
  const RouteConfig config;
  const int bvh_max_depth;  ///< bvh4_max_depth, walked once (every node) rather than per request
  FramesInFlight frames;    ///< the frames being sent, within config.frame_bytes
  LogSink log;              ///< the server's
};

/// `body` as JSON text. Strings that are not UTF-8 (a file or scene name in another encoding: they are bytes)
/// have each bad byte replaced by U+FFFD, so that no name can make a reply fail.
std::string json_text(const nlohmann::json& body);
/// Replies with `body` as JSON (200 unless `status` says otherwise).
void reply_json(Response& res, const nlohmann::json& body, int status = 200);
/// Replies with an error: status, X-PT-Error and {"error": message}.
void reply_error(Response& res, int status, const std::string& message);

/// `handler` with ParamError answered 400 and io's InputError (a file that
/// cannot be written) 500, each with its message.
Handler guarded(Handler handler);

/// The camera file's fields as JSON (the page shows them; the tests compare them).
nlohmann::json camera_json(const ViewCamera& c);
/// The view's settings as JSON, by the names the settings route takes.
nlohmann::json settings_json(const ViewSettings& s);

void add_view_routes(HttpServer& server, RouteContext& context);
void add_file_routes(HttpServer& server, RouteContext& context);
void add_bvh_routes(HttpServer& server, RouteContext& context);

}  // namespace pt::live
