// The live view's HTTP server: cpp-httplib's parsing and routing over
// connections with hard limits (connection_stream.h), a cap on the
// connections open at once, a bounded request body, and one log line for
// every request refused (status 400 and up) or timed out. Requests are
// framed plainly: no Range header (refused before httplib parses it), no
// Transfer-Encoding or Content-Encoding, a body only on a POST and only as
// Content-Length bytes within the limit; each is checked before any body is
// read, and a refusal closes the connection.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>

#include <httplib.h>

#include "connection_stream.h"

namespace pt::live {

struct ServerLimits {
  StreamLimits stream;
  std::chrono::milliseconds keep_alive{5000};  ///< an idle connection is closed after this long
  size_t max_connections = 48;                 ///< more at once are answered 503 and closed
  size_t threads = 64;                         ///< connections served at once (the rest wait their turn)
  size_t max_requests_per_connection = 1000;
  size_t max_body_bytes = 16 * 1024;  ///< larger bodies are refused with 413
};

/// Where log lines go (one line each, without the newline).
using LogSink = std::function<void(const std::string&)>;

/// `text` made safe for a one-line log: control and non-ASCII bytes as \xNN,
/// cut to `max` characters with "...".
std::string log_safe(const std::string& text, size_t max = 200);

class HttpServer : public httplib::Server {
 public:
  HttpServer(const ServerLimits& limits, LogSink log);

  /// Binds to host:port (port 0: any free port); the port bound, or -1.
  int bind(const std::string& host, int port);
  /// Installs `guard` as the pre-routing handler, after the server's own checks of the request's framing.
  void set_request_guard(HandlerWithResponse guard);
  /// Stops at once: connections end after the response under way (reads stop, writes get a short grace),
  /// then the listener closes. Hides httplib::Server::stop, which waits for every connection's deadline.
  void stop();
  bool stopping() const { return stopping_.load(); }
  void log(const std::string& line) const { log_(line); }
  /// Connections open now.
  size_t open_connections() const { return open_.load(); }

 private:
  bool process_and_close_socket(socket_t sock) override;
  /// Waits for the first byte of a next request; false when the connection idles out or the server stops.
  bool wait_for_request(int fd) const;
  /// Sends a bare response with `status` and closes nothing (best effort: the client may be gone).
  void send_bare(int fd, int status, const char* reason) const;
  /// Refuses a request whose body or framing the server does not take (status and X-PT-Error set); false if fine.
  bool refuse_framing(const httplib::Request& req, httplib::Response& res) const;

  ServerLimits limits_;
  LogSink log_;
  std::atomic<size_t> open_{0};
  std::atomic<bool> stopping_{false};
};

}  // namespace pt::live
