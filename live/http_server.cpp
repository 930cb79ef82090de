// The connection loop of cpp-httplib's server, redone over ConnectionStream:
// keep-alive, a request deadline answered with 408, a request size answered
// with 431, and too many connections answered with 503.
#include "http_server.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
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

/// Responses after which the connection is closed: the request was malformed,
/// so where the next one starts in the byte stream is unknown.
bool ends_connection(int status) { return status == 400 || status == 413 || status == 414 || status == 431; }

/// What httplib's own refusals mean (routes name theirs in X-PT-Error).
const char* reason(int status) {
  switch (status) {
    case 400: return "malformed request";
    case 404: return "no such route";
    case 405: return "method not allowed";
    case 413: return "request body too large";
    case 414: return "request line too long";
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
  set_logger([this](const httplib::Request& req, const httplib::Response& res) {
    t_last_status = res.status;
    if (res.status < 400) return;
    std::string why = res.get_header_value("X-PT-Error");
    log_("live: " + std::to_string(res.status) + " " + log_safe(req.method, 16) + " " + log_safe(req.target) +
         " from " + t_peer + ": " + (why.empty() ? reason(res.status) : why));
  });
}

int HttpServer::bind(const std::string& host, int port) {
  if (port == 0) return bind_to_any_port(host);
  return bind_to_port(host, port) ? port : -1;
}

bool HttpServer::wait_for_request(int fd) const {
  const auto deadline = std::chrono::steady_clock::now() + limits_.keep_alive;
  while (is_running() && std::chrono::steady_clock::now() < deadline) {
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
  ConnectionStream stream(sock, limits_.stream, *this);
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
    for (size_t left = limits_.max_requests_per_connection; left > 0 && is_running(); --left) {
      if (!stream.has_buffered() && !wait_for_request(sock)) break;
      stream.begin_request();
      bool closed = false;
      t_last_status = 0;
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
      if (!ok || closed || ends_connection(t_last_status)) break;
    }
  }
  open_.fetch_sub(1);
  shutdown(sock, SHUT_RDWR);
  close(sock);
  return ok;
}

}  // namespace pt::live
