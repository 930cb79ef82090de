// The live view's endpoints (docs/live_view.md lists them): the embedded
// page, the shared view's state and frames, camera moves and settings, the
// BVH overlays, Save camera and Render. Every request first passes the guard:
// its Host must be one the server answers to (no DNS rebinding), methods
// other than GET, HEAD and POST are refused, and every API request must carry
// the header X-PT-Live, which only the page itself can send (no cross-site
// use), and no Origin or Sec-Fetch-Site that names another site.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "bvh/scene_bvh4.h"
#include "http_server.h"
#include "render_session.h"

namespace pt::live {

struct RouteConfig {
  std::filesystem::path directory;    ///< where files a request names are written: the start directory
  std::filesystem::path camera_file;  ///< Save camera's file when the request names none
  std::filesystem::path image_file;   ///< Render's image when the request names none
  std::vector<std::string> hosts;     ///< Host header values accepted, in lower case (accepted_hosts)
  std::string scene_name;
  std::chrono::milliseconds frame_wait{10000};  ///< the longest a frame request waits (then 204)
  size_t frame_bytes = size_t(16) << 20;        ///< the frames being sent at once (FramesInFlight's budget)
};

/// Registers every route on `server`; `session` and `bvh` outlive it.
void add_routes(HttpServer& server, RenderSession& session, const SceneBvh4& bvh, const RouteConfig& config);

}  // namespace pt::live
