// What a route sees of a request and makes of its reply, apart from the
// server that carries them (http_server.h): the request's method, path,
// target as sent, parameters and headers; the reply's status, headers and
// body, a body sent from memory the reply keeps alive, or a reply that waits
// for something (a frame) without holding a thread. And log_safe, which makes
// any bytes fit a one-line log.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pt::live {

/// Where log lines go (one line each, without the newline).
using LogSink = std::function<void(const std::string&)>;

/// `text` made safe for a one-line log: control and non-ASCII bytes as \xNN, cut to `max` characters with "...".
std::string log_safe(const std::string& text, size_t max = 200);

using Headers = std::vector<std::pair<std::string, std::string>>;

struct Request {
  std::string method;
  std::string path;    ///< percent-decoded, without the query
  std::string target;  ///< the request line's target as sent (log lines name it)
  std::multimap<std::string, std::string> params;
  Headers headers;          ///< as sent, in order
  std::string remote_addr;  ///< the client's address, without the port
  uint64_t connection = 0;  ///< the connection's id among the clients' shares
  /// The first value of the header `name` (in any case), or "".
  std::string header(std::string_view name) const;
  size_t header_count(std::string_view name) const;
};

struct Response {
  int status = 200;
  std::string content_type = "text/plain";
  std::string body;
  Headers headers;
  /// Instead of `body`: these bytes, sent from memory that `keep` holds until the response is done (no copy).
  std::vector<std::string_view> parts;
  std::shared_ptr<const void> keep;
  /// A reply that waits: `ready` (any thread, must not block) is asked on wake() and once on registration;
  /// once it says so, `wait` has passed or the server stops, `finish` makes the reply.
  struct Wait {
    std::function<bool()> ready;
    std::chrono::milliseconds wait{0};
    std::function<void(Response&)> finish;
  };
  std::shared_ptr<Wait> deferred;

  void set_content(std::string text, std::string type) {
    body = std::move(text);
    content_type = std::move(type);
  }
  void set_header(std::string name, std::string value) { headers.emplace_back(std::move(name), std::move(value)); }
  /// The value of the header `name` set so far (exact case), or "".
  std::string header(std::string_view name) const;
};

using Handler = std::function<void(const Request&, Response&)>;

}  // namespace pt::live
