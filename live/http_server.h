// The live view's HTTP server: cpp-httplib's parsing and routing over
// connections with hard limits (connection_stream.h), connections shared
// fairly between clients (client_shares.h), and one log line for every
// request refused (status 400 and up) or timed out and every connection one
// client's share took from another. Requests are framed plainly and carry no
// body (no route reads one): no Range header (refused before httplib parses
// it), no Transfer-Encoding, Content-Encoding or multipart Content-Type, a
// Content-Length of 0 on a POST, Host and X-PT-Live as sent (not
// percent-encoded); each is checked before httplib reads or parses a body,
// and a refusal closes the connection.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <httplib.h>

#include "client_shares.h"
#include "connection_stream.h"

namespace pt::live {

struct ServerLimits {
  StreamLimits stream;
  ShareLimits shares;                          ///< connections at once, in all and per client; frame waits per client
  std::chrono::milliseconds keep_alive{5000};  ///< an idle connection is closed after this long
  size_t threads = 64;  ///< connections served at once: more than shares.connections, so that refusals find one
  size_t max_requests_per_connection = 1000;
};

/// Where log lines go (one line each, without the newline).
using LogSink = std::function<void(const std::string&)>;

/// `text` made safe for a one-line log: control and non-ASCII bytes as \xNN,
/// cut to `max` characters with "...".
std::string log_safe(const std::string& text, size_t max = 200);

class HttpServer : public httplib::Server {
 public:
  /// `now` is the clock of every deadline (none: steady_clock's).
  HttpServer(const ServerLimits& limits, LogSink log, NowFunction now = {});

  /// Binds to host:port (port 0: any free port); the port bound, or -1.
  int bind(const std::string& host, int port);
  /// Installs `guard` as the pre-routing handler, after the server's own checks of the request's framing.
  void set_request_guard(HandlerWithResponse guard);
  /// Stops at once: connections end after the response under way (reads stop, writes get a short grace),
  /// then the listener closes. Hides httplib::Server::stop, which waits for every connection's deadline.
  void stop();
  bool stopping() const { return stopping_.load(); }
  void log(const std::string& line) const { log_(line); }
  /// Connections open now (admitted and not yet closed or taken by another client).
  size_t open_connections() const { return shares_.open(); }
  /// The clients' shares: a frame request holds a FrameWait of them while it waits.
  ClientShares& shares() { return shares_; }

 private:
  bool process_and_close_socket(socket_t sock) override;
  /// Waits for the first byte of a next request; false when the connection idles out or the server stops.
  bool wait_for_request(int fd) const;
  /// Sends a bare response with `status` and closes nothing (best effort: the client may be gone).
  void send_bare(int fd, int status, const char* reason) const;
  /// Refuses a request whose body or framing the server does not take (status and X-PT-Error set); false if fine.
  bool refuse_framing(const httplib::Request& req, httplib::Response& res) const;
  /// Serves the requests of an admitted connection until it closes.
  bool serve(int sock, ConnectionStream& stream, uint64_t id, const std::string& who);

  ServerLimits limits_;
  LogSink log_;
  NowFunction now_;
  ClientShares shares_;
  const std::vector<std::string> literal_headers_{"host", "x-pt-live"};
  std::atomic<bool> stopping_{false};
};

}  // namespace pt::live
