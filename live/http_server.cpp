// The connection loop of cpp-httplib's server, redone over ConnectionStream:
// admission by the clients' shares (503 when a client holds its share, or the
// server is full and no client holds more than its share), keep-alive, a
// request deadline answered with 408, a request size answered with 431 (414
// for the request line), a Range header answered with 416, and the checks of
// a request's framing before its body is read.
#include "http_server.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
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
/// The id of that connection among the clients' shares (its phase changes as its requests are served).
thread_local uint64_t t_connection = 0;
/// The last response said "Connection: close": the connection ends after it.
thread_local bool t_close = false;

/// Responses after which the connection is closed: the request was malformed or
/// timed out, so where the next one starts in the byte stream is unknown.
bool ends_connection(int status) {
  return status == 400 || status == 408 || status == 411 || status == 413 || status == 414 || status == 415 ||
         status == 416 || status == 431;
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
    case 415: return "unsupported media type";
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

HttpServer::HttpServer(const ServerLimits& limits, LogSink log, NowFunction now)
    : limits_(limits),
      log_(std::move(log)),
      now_(now ? std::move(now) : NowFunction([] { return Clock::now(); })),
      shares_(limits.shares) {
  // SO_REUSEADDR only: a restart may bind while old connections linger, but no
  // second server can share the port (httplib's default, SO_REUSEPORT, lets it).
  set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  new_task_queue = [n = limits_.threads] { return new httplib::ThreadPool(n); };
  set_payload_max_length(0);  // no route reads a body (refuse_framing refuses one before httplib would read it)
  set_keep_alive_max_count(limits_.max_requests_per_connection);
  // Every response with status 400 and up passes here. A request that httplib found malformed because the stream
  // stopped it (at a Range header, at the size or time limit) is answered with the reason; a response after
  // which the connection closes says so.
  set_error_handler(HandlerWithResponse([this](const httplib::Request&, httplib::Response& res) {
    auto answer = [&res](int status, const std::string& why) {
      res.status = status;
      res.set_header("X-PT-Error", why);
      res.set_content(why + "\n", "text/plain");
      return HandlerResponse::Handled;
    };
    HandlerResponse handled = HandlerResponse::Unhandled;
    if (t_stream && t_stream->range_refused()) {
      handled = answer(416, "a Range header is not accepted (responses are sent whole)");
    } else if (t_stream && res.status == 400 && t_stream->headers_too_large()) {
      handled = answer(431, "request headers larger than " + std::to_string(CPPHTTPLIB_HEADER_MAX_LENGTH) +
                                " bytes a line or " + std::to_string(limits_.stream.request_bytes) + " in all");
    } else if (t_stream && res.status == 400 && t_stream->timed_out()) {
      handled =
          answer(408, "no complete request within " + std::to_string(limits_.stream.request_time.count()) + " ms");
    }
    if (ends_connection(res.status) && res.get_header_value("Connection") != "close")
      res.set_header("Connection", "close");
    return handled;
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
    shares_.set_phase(t_connection, ClientShares::Phase::kHandling);
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
  if (t_stream && t_stream->percent_encoded())
    return refuse(400, "Host and X-PT-Live are taken as sent: their values may not be percent-encoded");
  if (req.has_header("Transfer-Encoding"))
    return refuse(411, "Transfer-Encoding is not accepted: no request has a body");
  if (req.has_header("Content-Encoding")) return refuse(415, "Content-Encoding is not accepted: no request has a body");
  // httplib would parse a multipart body's part headers with std::regex, which recurses about 300 bytes of stack
  // per byte: a part header of a few thousand bytes overflows a thread's stack under some limits.
  std::string type = req.get_header_value("Content-Type");
  for (char& c : type) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (type.rfind("multipart/", 0) == 0) return refuse(415, "a multipart body is not accepted: no request has a body");
  const size_t lengths = req.get_header_value_count("Content-Length");
  if (lengths == 0) return req.method == "POST" && refuse(411, "a POST needs a Content-Length of 0 (no body)");
  if (lengths > 1) return refuse(400, "Content-Length is given more than once");
  const std::string text = req.get_header_value("Content-Length");
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos)
    return refuse(400, "Content-Length must be a decimal number, got \"" + log_safe(text, 40) + "\"");
  if (text.find_first_not_of('0') != std::string::npos)
    return refuse(413, "a body of " + text + " bytes is not accepted: " + log_safe(req.method, 16) + " " +
                           log_safe(req.path, 80) + " takes none (no request has a body)");
  return false;
}

void HttpServer::stop() {
  stopping_.store(true);
  httplib::Server::stop();
}

bool HttpServer::wait_for_request(int fd) const {
  const auto deadline = now_() + limits_.keep_alive;
  while (!stopping_.load() && now_() < deadline) {
    pollfd p{fd, POLLIN, 0};
    int r = poll(&p, 1, int(ConnectionStream::kSlice.count()));
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
  ConnectionStream stream(sock, limits_.stream, stopping_, now_, literal_headers_);
  std::string ip;
  int port = 0;
  stream.get_remote_ip_and_port(ip, port);
  const std::string who = ip + ":" + std::to_string(port);
  const std::string client = client_of(ip);
  // Taking another client's connection shuts its socket down: its thread's wait returns, and it closes.
  ClientShares::Admission a = shares_.admit(client, [sock] { shutdown(sock, SHUT_RDWR); });
  bool ok = false;
  if (a.refusal != ClientShares::Refusal::kNone) {
    send_bare(sock, 503, "Service Unavailable");
    const ShareLimits& l = limits_.shares;
    log_("live: 503 from " + who + ": " +
         (a.refusal == ClientShares::Refusal::kClientFull
              ? client + " has " + std::to_string(a.held) + " connections open, as many as one client may"
              : std::to_string(l.connections) + " connections open, none of them beyond its client's share") +
         "; refused");
  } else {
    if (!a.evicted_client.empty())
      log_("live: a connection of " + a.evicted_client + " closed for one of " + client + " (" +
           std::to_string(limits_.shares.connections) + " open: " + a.evicted_client + " held the most)");
    ok = serve(sock, stream, a.id, who);
    shares_.leave(a.id);
  }
  shutdown(sock, SHUT_RDWR);
  close(sock);
  return ok;
}

bool HttpServer::serve(int sock, ConnectionStream& stream, uint64_t id, const std::string& who) {
  t_stream = &stream;
  t_peer = who;
  t_connection = id;
  stream.set_on_response([this, id] { shares_.set_phase(id, ClientShares::Phase::kWriting); });
  bool ok = false;
  for (size_t left = limits_.max_requests_per_connection; left > 0 && !stopping_.load(); --left) {
    shares_.set_phase(id, ClientShares::Phase::kIdle);
    if (!stream.has_buffered() && !wait_for_request(sock)) break;
    stream.begin_request();  // the request's deadline starts before the phase says so
    shares_.set_phase(id, ClientShares::Phase::kReading);
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
    if (!stream.wrote() && stream.line_too_large()) {
      send_bare(sock, 414, "URI Too Long");
      log_("live: 414 from " + who + ": request line longer than " + std::to_string(limits_.stream.request_bytes) +
           " bytes; closed");
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
  t_stream = nullptr;
  t_connection = 0;
  return ok;
}

}  // namespace pt::live
