// libmicrohttpd's callbacks: a connection is admitted by the clients' shares
// when it opens; a request's phase changes at its line (reading), its
// headers (handling: the framing is checked before any body is read, then
// the guard and the route run once the request is complete) and its
// response (writing). A reply that waits suspends its connection; one
// thread resumes it when it is ready (woken) or due, and ends connections
// whose phase outlasts its limit.
#include "http_server.h"

#include <microhttpd.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>

namespace pt::live {
namespace {

constexpr std::chrono::milliseconds kStopGrace{500};  ///< for the replies the stop makes to be sent
constexpr std::chrono::milliseconds kSlice{100};      ///< how often waits and deadlines are looked at

/// A TCP connection (libmicrohttpd's socket context).
struct Connection {
  uint64_t id = 0;  ///< among the shares (0: refused)
  std::string peer;
};

/// A request, from its line on (libmicrohttpd's request context).
struct Exchange {
  Connection* connection = nullptr;
  Request request;
  bool headers_seen = false, answered = false;
  std::shared_ptr<Response::Wait> wait;  ///< the reply waits for this
  Clock::time_point due;                 ///< ... until then
  bool stop_reply = false;               ///< its reply is one the stop waits for
};

Connection* connection_of(MHD_Connection* c) {
  const MHD_ConnectionInfo* i = MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
  return i ? static_cast<Connection*>(i->socket_context) : nullptr;
}

std::string address_text(const sockaddr* a, int& port) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a && a->sa_family == AF_INET) {
    inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(a)->sin_addr, text, sizeof text);
    port = ntohs(reinterpret_cast<const sockaddr_in*>(a)->sin_port);
  } else if (a && a->sa_family == AF_INET6) {
    inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(a)->sin6_addr, text, sizeof text);
    port = ntohs(reinterpret_cast<const sockaddr_in6*>(a)->sin6_port);
  }
  return text;
}

void refuse(Response& res, int status, const std::string& why) {
  res.status = status;
  res.set_header("X-PT-Error", why);
  res.set_content(why + "\n", "text/plain");
}

/// Why libmicrohttpd refused a request itself.
const char* reason(unsigned status) {
  switch (status) {
    case 414: return "request line too long";
    case 431: return "request headers larger than a connection's memory";
    case 413: return "request too large";
    default: return "malformed request";
  }
}

/// Refuses a request whose bytes the server cannot take as read: header lines not exactly "Name: value" with
/// CRLF (a NUL ends a value early, so the check counts the bytes), or a body of any kind.
bool refuse_framing(const Request& req, const std::string& version, size_t header_bytes, Response& res) {
  size_t read = req.method.size() + req.target.size() + version.size() + 4 + 2;
  for (const auto& [name, value] : req.headers) read += name.size() + value.size() + 4;
  if (read != header_bytes)
    refuse(res, 400,
           "header lines must be \"Name: value\" ending in CRLF, without NUL bytes (" + std::to_string(read) + " of " +
               std::to_string(header_bytes) + " bytes read)");
  else if (req.header_count("Transfer-Encoding"))
    refuse(res, 411, "Transfer-Encoding is not accepted: no request has a body");
  else if (req.header_count("Content-Length") > 1) refuse(res, 400, "Content-Length is given more than once");
  else if (std::string n = req.header("Content-Length"); n.find_first_not_of('0') != std::string::npos)
    refuse(res, 413,
           "a body of " + log_safe(n, 20) + " bytes is not accepted: " + log_safe(req.method, 16) + " " +
               log_safe(req.path, 80) + " takes none (no request has a body)");
  return res.status >= 400;
}

/// Runs `make` for `res`; an exception is a 500 with its message.
void make_reply(const std::function<void(Response&)>& make, Response& res) {
  try {
    make(res);
  } catch (const std::exception& e) {
    res = Response{};
    refuse(res, 500, e.what());
  }
}

}  // namespace

/// The replies waiting, and the thread that resumes them.
struct HttpServer::Waiting {
  std::mutex mutex;
  std::condition_variable cv;
  bool woken = false, closing = false, quit = false;
  std::vector<std::pair<MHD_Connection*, Exchange*>> replies;
  size_t stop_replies = 0;  ///< replies the stop made (or resumed) and waits for
  std::thread thread;
};

struct HttpServer::Callbacks {
  static void connection(void* cls, MHD_Connection* c, void** context, MHD_ConnectionNotificationCode code) {
    HttpServer& s = *static_cast<HttpServer*>(cls);
    if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
      auto* conn = static_cast<Connection*>(*context);
      if (conn && conn->id) s.shares_.leave(conn->id);
      delete conn;
      return;
    }
    int port = 0;
    const MHD_ConnectionInfo* a = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    const std::string ip = address_text(a ? a->client_addr : nullptr, port), client = client_of(ip);
    const int fd = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD)->connect_fd;
    auto* conn = new Connection{0, ip + ":" + std::to_string(port)};
    *context = conn;
    // Taking a connection shuts its socket down: libmicrohttpd then closes it.
    ClientShares::Admission adm = s.shares_.admit(
        client, conn->peer, [fd] { shutdown(fd, SHUT_RDWR); }, s.now_());
    if (adm.refusal != ClientShares::Refusal::kNone) {  // the line first: the client sees the close after it
      s.log_("live: refused a connection from " + conn->peer + ": " +
             (adm.refusal == ClientShares::Refusal::kClientFull
                  ? client + " has " + std::to_string(adm.held) + " connections open, as many as one client may"
                  : std::to_string(s.limits_.shares.connections) +
                        " connections open, none of them beyond its client's share"));
      shutdown(fd, SHUT_RDWR);
      return;
    }
    conn->id = adm.id;
    if (!adm.evicted_client.empty())
      s.log_("live: a connection of " + adm.evicted_client + " closed for one of " + client + " (" +
             std::to_string(s.limits_.shares.connections) + " open: " + adm.evicted_client + " held the most)");
  }

  static void* request_line(void* cls, const char* uri, MHD_Connection* c) {
    HttpServer& s = *static_cast<HttpServer*>(cls);
    auto* x = new Exchange;
    x->connection = connection_of(c);
    x->request.target = uri;
    if (x->connection) s.shares_.set_phase(x->connection->id, ClientShares::Phase::kReading, s.now_());
    return x;
  }

  static MHD_Result value(void* into, MHD_ValueKind kind, const char* key, size_t key_size, const char* value,
                          size_t value_size) {
    std::string k(key, key_size), v(value ? value : "", value ? value_size : 0);
    if (kind == MHD_HEADER_KIND) static_cast<Request*>(into)->headers.emplace_back(std::move(k), std::move(v));
    else static_cast<Request*>(into)->params.emplace(std::move(k), std::move(v));
    return MHD_YES;
  }

  static MHD_Result request(void* cls, MHD_Connection* c, const char* url, const char* method, const char* version,
                            const char*, size_t* upload_size, void** context) {
    HttpServer& s = *static_cast<HttpServer*>(cls);
    auto* x = static_cast<Exchange*>(*context);
    // No line seen, a connection refused or taken, or a body that the framing let through: close.
    if (!x || !x->connection || !x->connection->id || *upload_size != 0) return MHD_NO;
    Response res;
    if (!x->headers_seen) {  // the headers are in, the body (if any) is not read yet
      x->headers_seen = true;
      Request& req = x->request;
      req.method = method;
      req.path = url;
      req.connection = x->connection->id;
      req.remote_addr = x->connection->peer.substr(0, x->connection->peer.rfind(':'));
      MHD_get_connection_values_n(c, MHD_HEADER_KIND, value, &req);
      MHD_get_connection_values_n(c, MHD_GET_ARGUMENT_KIND, value, &req);
      s.shares_.set_phase(req.connection, ClientShares::Phase::kHandling, s.now_());
      const size_t bytes = MHD_get_connection_info(c, MHD_CONNECTION_INFO_REQUEST_HEADER_SIZE)->header_size;
      // A reply now, before the body: libmicrohttpd then closes the connection without reading it.
      return refuse_framing(req, version, bytes, res) ? respond(s, c, *x, res) : MHD_YES;
    }
    std::shared_ptr<Response::Wait> wait = std::move(x->wait);  // set: resumed
    if (!wait) {
      s.dispatch(x->request, res);
      wait = std::move(res.deferred);
      if (wait) res = Response{};
      if (wait && !wait->ready() && suspend(s, c, *x, wait)) return MHD_YES;
    }
    if (wait && s.stopping_.load()) refuse(res, 503, "the server is stopping");
    else if (wait) make_reply(wait->finish, res);
    return respond(s, c, *x, res);
  }

  static void completed(void* cls, MHD_Connection* c, void** context, MHD_RequestTerminationCode) {
    HttpServer& s = *static_cast<HttpServer*>(cls);
    auto* x = static_cast<Exchange*>(*context);
    if (!x) return;
    const MHD_ConnectionInfo* i = MHD_get_connection_info(c, MHD_CONNECTION_INFO_HTTP_STATUS);
    const unsigned status = i ? i->http_status : 0;
    if (!x->answered && status >= 400 && x->connection)
      s.log_("live: " + std::to_string(status) + " " + log_safe(x->request.target) + " from " + x->connection->peer +
             ": " + reason(status));
    if (x->stop_reply) {
      std::lock_guard lock(s.waiting_->mutex);
      --s.waiting_->stop_replies;
      s.waiting_->cv.notify_all();
    }
    if (x->connection) s.shares_.set_phase(x->connection->id, ClientShares::Phase::kIdle, s.now_());
    delete x;
    *context = nullptr;
  }

  static void release(void* keep) { delete static_cast<std::shared_ptr<const void>*>(keep); }

  /// Queues `res`; every refusal (400 and up) closes its connection and is one log line.
  static MHD_Result respond(HttpServer& s, MHD_Connection* c, Exchange& x, Response& res) {
    MHD_Response* r = nullptr;
    if (res.parts.empty()) {
      r = MHD_create_response_from_buffer(res.body.size(), res.body.data(), MHD_RESPMEM_MUST_COPY);
    } else {
      std::vector<MHD_IoVec> iov;
      for (std::string_view p : res.parts) iov.push_back({p.data(), p.size()});
      r = MHD_create_response_from_iovec(iov.data(), unsigned(iov.size()), release,
                                         new std::shared_ptr<const void>(std::move(res.keep)));
    }
    if (!r) return MHD_NO;
    for (const Headers* list : {&s.default_headers_, &res.headers})
      for (const auto& [name, value] : *list) MHD_add_response_header(r, name.c_str(), value.c_str());
    MHD_add_response_header(r, "Content-Type", res.content_type.c_str());
    const bool stopping = s.stopping_.load();
    if (res.status >= 400 || stopping) MHD_add_response_header(r, "Connection", "close");
    if (res.status >= 400 && !(res.status == 503 && stopping)) {
      const std::string why = res.header("X-PT-Error");
      s.log_("live: " + std::to_string(res.status) + " " + log_safe(x.request.method, 16) + " " +
             log_safe(x.request.target) + " from " + x.connection->peer + ": " + (why.empty() ? "refused" : why));
    }
    if (stopping && !x.stop_reply) {
      std::lock_guard lock(s.waiting_->mutex);
      x.stop_reply = true;
      ++s.waiting_->stop_replies;
    }
    x.answered = true;
    s.shares_.set_phase(x.connection->id, ClientShares::Phase::kWriting, s.now_());
    const MHD_Result queued = MHD_queue_response(c, unsigned(res.status), r);
    MHD_destroy_response(r);
    return queued;
  }

  /// Suspends the connection until `wait` is over; false (reply now) once the server stops.
  static bool suspend(HttpServer& s, MHD_Connection* c, Exchange& x, std::shared_ptr<Response::Wait> wait) {
    Waiting& w = *s.waiting_;
    std::lock_guard lock(w.mutex);
    if (w.closing) return false;
    x.wait = std::move(wait);
    x.due = s.now_() + x.wait->wait;
    MHD_suspend_connection(c);
    w.replies.emplace_back(c, &x);
    w.woken = true;  // what it waits for may have come meanwhile
    w.cv.notify_all();
    return true;
  }
};

HttpServer::HttpServer(const ServerLimits& limits, LogSink log, NowFunction now)
    : limits_(limits),
      log_(std::move(log)),
      now_(now ? std::move(now) : NowFunction([] { return Clock::now(); })),
      shares_(limits.shares),
      waiting_(std::make_unique<Waiting>()) {}

HttpServer::~HttpServer() {
  stop();
  if (listen_fd_ >= 0) close(listen_fd_);
}

int HttpServer::bind(const std::string& host, int port) {
  addrinfo hints{}, *found = nullptr;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return -1;
  int fd = socket(found->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  // SO_REUSEADDR only: a restart may bind while old connections linger, but no second server shares the port.
  int yes = 1;
  if (fd >= 0) setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  const bool bound = fd >= 0 && ::bind(fd, found->ai_addr, found->ai_addrlen) == 0 && listen(fd, SOMAXCONN) == 0;
  freeaddrinfo(found);
  sockaddr_storage a{};
  socklen_t length = sizeof a;
  if (!bound || getsockname(fd, reinterpret_cast<sockaddr*>(&a), &length) != 0) {
    if (fd >= 0) close(fd);
    return -1;
  }
  listen_fd_ = fd;
  int bound_port = 0;
  address_text(reinterpret_cast<const sockaddr*>(&a), bound_port);
  return bound_port;
}

bool HttpServer::start() {
  if (listen_fd_ < 0 || daemon_) return false;
  waiting_->thread = std::thread([this] { watch(); });
  sockaddr_storage a{};
  socklen_t length = sizeof a;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &length);
  const unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_EPOLL | MHD_ALLOW_SUSPEND_RESUME |
                         (a.ss_family == AF_INET6 ? MHD_USE_IPv6 : 0);
  daemon_ = MHD_start_daemon(flags, 0, nullptr, nullptr, &Callbacks::request, this, MHD_OPTION_LISTEN_SOCKET,
                             listen_fd_, MHD_OPTION_THREAD_POOL_SIZE, limits_.threads, MHD_OPTION_CONNECTION_LIMIT,
                             unsigned(limits_.max_sockets), MHD_OPTION_CONNECTION_MEMORY_LIMIT,
                             limits_.connection_bytes, MHD_OPTION_NOTIFY_CONNECTION, &Callbacks::connection, this,
                             MHD_OPTION_URI_LOG_CALLBACK, &Callbacks::request_line, this, MHD_OPTION_NOTIFY_COMPLETED,
                             &Callbacks::completed, this, MHD_OPTION_END);
  if (!daemon_) stop();
  return daemon_ != nullptr;
}

void HttpServer::stop() {
  Waiting& w = *waiting_;
  std::unique_lock lock(w.mutex);
  if (!w.thread.joinable()) return;
  stopping_.store(true);
  w.closing = w.woken = true;
  w.cv.notify_all();
  // The replies the stop makes (every waiting one: 503) get a short grace to be sent, on the real clock:
  // whatever the clients do, the stop ends within it.
  w.cv.wait_for(lock, kStopGrace, [&] { return w.replies.empty() && w.stop_replies == 0; });
  w.quit = true;
  w.cv.notify_all();
  lock.unlock();
  w.thread.join();
  if (daemon_) MHD_stop_daemon(daemon_);
  daemon_ = nullptr;
}

void HttpServer::get(const std::string& path, Handler handler) { get_routes_[path] = std::move(handler); }
void HttpServer::post(const std::string& path, Handler handler) { post_routes_[path] = std::move(handler); }

void HttpServer::wake() {
  {
    std::lock_guard lock(waiting_->mutex);
    waiting_->woken = true;
  }
  waiting_->cv.notify_all();
}

void HttpServer::dispatch(const Request& req, Response& res) const {
  if (stopping_.load()) return refuse(res, 503, "the server is stopping");
  if (guard_) guard_(req, res);
  if (res.status >= 400) return;
  const auto& routes = req.method == "POST" ? post_routes_ : get_routes_;  // HEAD: GET without the body
  auto route = routes.find(req.path);
  if (route == routes.end() || (req.method != "POST" && req.method != "GET" && req.method != "HEAD"))
    return refuse(res, 404, "no such route");
  make_reply([&](Response& r) { route->second(req, r); }, res);
}

void HttpServer::watch() {
  Waiting& w = *waiting_;
  std::unique_lock lock(w.mutex);
  while (!w.quit) {
    w.cv.wait_for(lock, kSlice, [&] { return w.woken || w.quit; });
    w.woken = false;
    const auto replies = w.replies;
    const bool closing = w.closing;
    lock.unlock();
    // Asked without the lock: `ready` may take the render's.
    std::vector<std::pair<MHD_Connection*, Exchange*>> over;
    for (const auto& r : replies)
      if (closing || now_() >= r.second->due || r.second->wait->ready()) over.push_back(r);
    end_overdue();
    lock.lock();
    for (const auto& r : over) {
      std::erase(w.replies, r);
      r.second->stop_reply = closing;
      w.stop_replies += closing;
    }
    lock.unlock();
    for (const auto& r : over) MHD_resume_connection(r.first);
    lock.lock();
  }
}

void HttpServer::end_overdue() {
  const ClientShares::PhaseLimits limits{limits_.keep_alive, limits_.request_time, limits_.response_time};
  for (const ClientShares::Overdue& o : shares_.end_overdue(now_(), limits)) {
    if (o.phase == ClientShares::Phase::kReading)
      log_("live: closed the connection of " + o.peer + ": no complete request within " +
           std::to_string(limits_.request_time.count()) + " ms");
    else if (o.phase == ClientShares::Phase::kWriting)
      log_("live: closed the connection of " + o.peer + ": its response was not taken within " +
           std::to_string(limits_.response_time.count()) + " ms");
  }
}

}  // namespace pt::live
