// The connection loop of cpp-httplib's server, redone over ConnectionStream:
// keep-alive, a request deadline answered with 408, a request size answered
// with 431, too many connections answered with 503, a Range header answered
// with 416, and the checks of a request's framing before its body is read.
#include "http_server.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>

namespace pt::live {

namespace {

/// The status of the last response written on this thread (the logger sees
/// every response, on the thread that serves its connection).
thread_local int t_last_status = 0;
/// The client of the connection this thread serves ("address:port"), for log lines
/// about requests too malformed to name their sender.
thread_local std::string t_peer;
/// The stream of the connection this thread serves (the error handler asks it why a request failed).
thread_local const ConnectionStream* t_stream = nullptr;
/// The last response said "Connection: close": the connection ends after it.
thread_local bool t_close = false;

/// Responses after which the connection is closed: the request was malformed,
/// so where the next one starts in the byte stream is unknown.
bool ends_connection(int status) {
  return status == 400 || status == 411 || status == 413 || status == 414 || status == 415 || status == 416 ||
         status == 431;
}

/// What httplib's own refusals mean (routes name theirs in X-PT-Error).
const char* reason(int status) {
  switch (status) {
    case 400: return "malformed request";
    case 404: return "no such route";
    case 405: return "method not allowed";
    case 411: return "length required";
    case 413: return "request body too large";
    case 414: return "request line too long";
    case 415: return "unsupported content encoding";
    case 416: return "bad range";
    case 431: return "request headers too large";
    default: return "refused";
  }
}

}  // namespace

std::string log_safe(const std::string& text, size_t max) {
  std::string out;
  for (unsigned char c : text) {
    if (out.size() >= max) {
      out += "...";
      break;
    }
    if (c >= 0x20 && c < 0x7f) {
      out += char(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}

HttpServer::HttpServer(const ServerLimits& limits, LogSink log) : limits_(limits), log_(std::move(log)) {
  // SO_REUSEADDR only: a restart may bind while old connections linger, but no
  // second server can share the port (httplib's default, SO_REUSEPORT, lets it).
  set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  new_task_queue = [n = limits_.threads] { return new httplib::ThreadPool(n); };
  set_payload_max_length(limits_.max_body_bytes);
  set_keep_alive_max_count(limits_.max_requests_per_connection);
  // A request stopped at its Range header (connection_stream.h) fails as malformed; it is answered 416.
  set_error_handler(HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
    if (!t_stream || !t_stream->range_refused()) return HandlerResponse::Unhandled;
    res.status = 416;
    res.set_header("X-PT-Error", "a Range header is not accepted (responses are sent whole)");
    return HandlerResponse::Handled;
  }));
  set_logger([this](const httplib::Request& req, const httplib::Response& res) {
    t_last_status = res.status;
    t_close = res.get_header_value("Connection") == "close";
    if (res.status < 400 || (res.status == 503 && stopping_.load())) return;  // requests ended by the stop
    std::string why = res.get_header_value("X-PT-Error");
    log_("live: " + std::to_string(res.status) + " " + log_safe(req.method, 16) + " " + log_safe(req.target) +
         " from " + t_peer + ": " + (why.empty() ? reason(res.status) : why));
  });
}

int HttpServer::bind(const std::string& host, int port) {
  if (port == 0) return bind_to_any_port(host);
  return bind_to_port(host, port) ? port : -1;
}

void HttpServer::set_request_guard(HandlerWithResponse guard) {
  set_pre_routing_handler([this, guard = std::move(guard)](const httplib::Request& req, httplib::Response& res) {
    if (refuse_framing(req, res)) {
      res.set_header("Connection", "close");  // the body, if any, is not read: the next request's start is unknown
      return HandlerResponse::Handled;
    }
    return guard(req, res);
  });
}

bool HttpServer::refuse_framing(const httplib::Request& req, httplib::Response& res) const {
  auto refuse = [&res](int status, const std::string& why) {
    res.status = status;
    res.set_header("X-PT-Error", why);
    res.set_content(why + "\n", "text/plain");
    return true;
  };
  if (req.has_header("Range")) return refuse(416, "a Range header is not accepted (responses are sent whole)");
  if (req.has_header("Transfer-Encoding"))
    return refuse(411, "Transfer-Encoding is not accepted: a body is sent with Content-Length");
  if (req.has_header("Content-Encoding"))
    return refuse(415, "Content-Encoding is not accepted: a body is taken as sent");
  const size_t lengths = req.get_header_value_count("Content-Length");
  if (lengths == 0) return req.method == "POST" && refuse(411, "a POST needs a Content-Length (0 without a body)");
  if (lengths > 1) return refuse(400, "Content-Length is given more than once");
  const std::string text = req.get_header_value("Content-Length");
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos)
    return refuse(400, "Content-Length must be a decimal number, got \"" + log_safe(text, 40) + "\"");
  const size_t length = std::stoull(text);
  if (length > 0 && req.method != "POST") return refuse(400, "a " + req.method + " takes no body");
  if (length > limits_.max_body_bytes)
    return refuse(413,
                  "a body of " + text + " bytes is more than the " + std::to_string(limits_.max_body_bytes) + " taken");
  return false;
}

void HttpServer::stop() {
  stopping_.store(true);
  httplib::Server::stop();
}

bool HttpServer::wait_for_request(int fd) const {
  const auto deadline = std::chrono::steady_clock::now() + limits_.keep_alive;
  while (!stopping_.load() && std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    int r = poll(&p, 1, 100);
    if (r > 0) return (p.revents & POLLIN) != 0;
    if (r < 0 && errno != EINTR) return false;
  }
  return false;
}

void HttpServer::send_bare(int fd, int status, const char* reason) const {
  std::string head =
      "HTTP/1.1 " + std::to_string(status) + " " + reason + "\r\nConnection: close\r\nContent-Length: 0\r\n\r\n";
  ssize_t ignored = send(fd, head.data(), head.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  (void)ignored;
}

bool HttpServer::process_and_close_socket(socket_t sock) {
  // A response goes out as a head and a body; without TCP_NODELAY the body
  // would wait for the head's acknowledgement (up to 40 ms of delayed ACK).
  int yes = 1;
  setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  ConnectionStream stream(sock, limits_.stream, stopping_);
  t_stream = &stream;
  std::string ip;
  int port = 0;
  stream.get_remote_ip_and_port(ip, port);
  const std::string who = ip + ":" + std::to_string(port);
  t_peer = who;
  bool ok = false;
  if (open_.fetch_add(1) >= limits_.max_connections) {
    send_bare(sock, 503, "Service Unavailable");
    log_("live: 503 from " + who + ": more than " + std::to_string(limits_.max_connections) +
         " connections open; refused");
  } else {
    for (size_t left = limits_.max_requests_per_connection; left > 0 && !stopping_.load(); --left) {
      if (!stream.has_buffered() && !wait_for_request(sock)) break;
      stream.begin_request();
      bool closed = false;
      t_last_status = 0;
      t_close = false;
      ok = process_request(stream, left == 1, closed, nullptr);
      if (!stream.wrote() && stream.timed_out()) {
        send_bare(sock, 408, "Request Timeout");
        log_("live: 408 from " + who + ": no complete request within " +
             std::to_string(limits_.stream.request_time.count()) + " ms; closed");
        break;
      }
      if (!stream.wrote() && stream.too_large()) {
        send_bare(sock, 431, "Request Header Fields Too Large");
        log_("live: 431 from " + who + ": request larger than " + std::to_string(limits_.stream.request_bytes) +
             " bytes; closed");
        break;
      }
      if (!ok || closed || t_close || ends_connection(t_last_status)) break;
    }
  }
  t_stream = nullptr;
  open_.fetch_sub(1);
  shutdown(sock, SHUT_RDWR);
  close(sock);
  return ok;
}

}  // namespace pt::live
