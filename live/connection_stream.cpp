// poll() with deadlines, recv() through a small buffer, send() without SIGPIPE.
#include "connection_stream.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace pt::live {
namespace {

constexpr std::chrono::milliseconds kSlice{100};

void address_of(const sockaddr_storage& a, std::string& ip, int& port) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
    port = ntohs(v4.sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
    port = ntohs(v6.sin6_port);
  }
  ip = text;
}

}  // namespace

ConnectionStream::ConnectionStream(int fd, const StreamLimits& limits, const httplib::Server& server)
    : fd_(fd), limits_(limits), server_(server) {
  begin_request();
}

void ConnectionStream::begin_request() {
  read_deadline_ = Clock::now() + limits_.request_time;
  request_bytes_ = len_ - pos_;
  timed_out_ = too_large_ = wrote_ = writing_ = false;
}

bool ConnectionStream::wait(short events, Clock::time_point deadline) const {
  for (;;) {
    const Clock::time_point now = Clock::now();
    if (now >= deadline) {
      timed_out_ = true;
      return false;
    }
    if (!server_.is_running()) return false;
    auto slice = std::min<Clock::duration>(deadline - now, kSlice);
    pollfd p{fd_, events, 0};
    int r = poll(&p, 1, int(std::chrono::duration_cast<std::chrono::milliseconds>(slice).count()) + 1);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return false;
    if (r > 0) return (p.revents & (events | POLLHUP | POLLERR)) != 0;
  }
}

bool ConnectionStream::is_readable() const { return pos_ < len_ || wait(POLLIN, read_deadline_); }

bool ConnectionStream::is_writable() const {
  return wait(POLLOUT, writing_ ? write_deadline_ : Clock::now() + limits_.response_time);
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
  if (pos_ == len_) {
    if (request_bytes_ >= limits_.request_bytes) {
      too_large_ = true;
      return -1;
    }
    if (!wait(POLLIN, read_deadline_)) return -1;
    ssize_t n;
    do {
      n = recv(fd_, buffer_, std::min(sizeof buffer_, limits_.request_bytes - request_bytes_), 0);
    } while (n < 0 && errno == EINTR);
    if (n <= 0) return n;
    pos_ = 0;
    len_ = size_t(n);
    request_bytes_ += size_t(n);
  }
  size_t n = std::min(size, len_ - pos_);
  std::memcpy(ptr, buffer_ + pos_, n);
  pos_ += n;
  return ssize_t(n);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
  if (!writing_) {
    writing_ = true;
    write_deadline_ = Clock::now() + limits_.response_time;
  }
  if (!wait(POLLOUT, write_deadline_)) return -1;
  ssize_t n;
  do { n = send(fd_, ptr, size, MSG_NOSIGNAL); } while (n < 0 && errno == EINTR);
  if (n > 0) wrote_ = true;
  return n;
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (getpeername(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) address_of(a, ip, port);
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) address_of(a, ip, port);
}

}  // namespace pt::live
