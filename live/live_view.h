// pathtracer --serve: the live view of one scene. Builds the BVH4, starts
// the render session and the HTTP server, prints the page's address, and
// serves until asked to stop (Ctrl-C).
#pragma once

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "http_server.h"
#include "kernels/scene/scene.h"
#include "render_session.h"

namespace pt::live {

struct LiveOptions {
  std::string bind = "127.0.0.1";     ///< address to listen on (--bind)
  int port = 8184;                    ///< 0: any free port
  std::filesystem::path directory;    ///< where files a request names are written: the start directory
  std::filesystem::path camera_file;  ///< Save camera's default file
  std::filesystem::path image_file;   ///< Render's default image
  SessionConfig session;
  ServerLimits limits;
  bool quiet = false;  ///< no address line (tests read it all the same: it goes to stdout unless quiet)
};

/// Serves until `stop` becomes true; returns the exit code (0). Throws
/// InputError when the address cannot be bound.
int serve_live_view(const Scene& scene, const LiveOptions& options, const std::atomic<bool>& stop);

/// Whether `address` is a loopback address (127.0.0.0/8, ::1, "localhost").
bool is_loopback(const std::string& address);

/// The Host header values (lower case, "host:port", IPv6 in brackets) a server bound to `bind` answers:
/// 127.0.0.1, localhost, [::1] and `bind` itself; for any other address than a loopback one also this
/// machine's name, and for 0.0.0.0 and :: every address of its interfaces. Any other Host is refused
/// (no DNS rebinding: a name an attacker controls never matches).
std::vector<std::string> accepted_hosts(const std::string& bind, int port);

}  // namespace pt::live
