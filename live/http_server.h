// The live view's HTTP server: GNU libmicrohttpd (a thread pool, a memory
// limit per connection) through its public API, with exact-path routes, a
// guard run before any route, replies that wait without holding a thread
// (suspended connections, resumed on wake()), connections shared between
// clients (client_shares.h) with a deadline for each phase of a connection,
// and one log line for every request refused (status 400 and up), every
// connection closed for a deadline and every connection one client's share
// took from another. No request has a body: one is refused before it is
// read, and so is a request whose header bytes are not what the server read
// from them (a NUL ends a value early). Every refusal closes its connection.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "client_shares.h"
#include "http_request.h"

struct MHD_Daemon;

namespace pt::live {

/// The clock of the server's deadlines: steady_clock's time, or a test's.
using Clock = std::chrono::steady_clock;
using NowFunction = std::function<Clock::time_point()>;

struct ServerLimits {
  std::chrono::milliseconds keep_alive{5000};      ///< an idle connection closes after this long
  std::chrono::milliseconds request_time{5000};    ///< from a request's line to the end of its headers
  std::chrono::milliseconds response_time{30000};  ///< for all of a response's bytes to be taken
  size_t connection_bytes = 64 * 1024;             ///< a connection's memory: its request's line and headers fit in it
  ShareLimits shares;       ///< connections at once, in all and per client; frame waits per client
  unsigned threads = 4;     ///< libmicrohttpd's thread pool (waiting replies hold none)
  size_t max_sockets = 64;  ///< open at once: more than shares.connections, so that a refusal finds one
};

class HttpServer {
 public:
  /// `now` is the clock of every deadline (none: steady_clock's).
  HttpServer(const ServerLimits& limits, LogSink log, NowFunction now = {});
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// Listens on host:port (port 0: any free port); the port, or -1.
  int bind(const std::string& host, int port);
  /// Starts serving; false if libmicrohttpd cannot start.
  bool start();
  /// Stops within half a second whatever the clients do: waiting replies are made (503: the server is
  /// stopping), and every connection closes once they are sent or the half second passes.
  void stop();
  bool stopping() const { return stopping_.load(); }

  void get(const std::string& path, Handler handler);
  void post(const std::string& path, Handler handler);
  /// Runs before the routes: refuses a request by setting a status of 400 and up.
  void set_guard(Handler guard) { guard_ = std::move(guard); }
  void set_default_headers(Headers headers) { default_headers_ = std::move(headers); }
  /// Something a waiting reply waits for may have happened (any thread, never blocks).
  void wake();

  void log(const std::string& line) const { log_(line); }
  /// Connections open now (admitted and not yet closed or taken by another client).
  size_t open_connections() const { return shares_.open(); }
  ClientShares& shares() { return shares_; }

 private:
  struct Callbacks;  // libmicrohttpd's callbacks, in the .cpp
  struct Waiting;
  void dispatch(const Request& req, Response& res) const;
  /// Polls the waiting replies and the connections' deadlines until the server stops.
  void watch();
  void end_overdue();

  ServerLimits limits_;
  LogSink log_;
  NowFunction now_;
  ClientShares shares_;
  Handler guard_;
  Headers default_headers_;
  std::map<std::string, Handler> get_routes_, post_routes_;
  int listen_fd_ = -1;
  MHD_Daemon* daemon_ = nullptr;
  std::atomic<bool> stopping_{false};
  std::unique_ptr<Waiting> waiting_;
};

}  // namespace pt::live
