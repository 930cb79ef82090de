// poll() with deadlines, recv() through a small buffer, send() without SIGPIPE,
// and the header names followed byte by byte.
#include "connection_stream.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "response_head.h"

namespace pt::live {
namespace {

constexpr size_t kMaxNameBytes = 32;  ///< header names compared with literal_headers (longer ones are none of them)

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

ConnectionStream::ConnectionStream(int fd, const StreamLimits& limits, const std::atomic<bool>& stopping,
                                   const NowFunction& now, const std::vector<std::string>& literal_headers)
    : fd_(fd), limits_(limits), stopping_(stopping), now_(now), literal_headers_(literal_headers) {
  begin_request();
}

void ConnectionStream::begin_request() {
  read_deadline_ = now_() + limits_.request_time;
  request_bytes_ = len_ - pos_;
  timed_out_ = too_large_ = wrote_ = writing_ = false;
  expect_head_ = true;
  part_ = Part::kRequestLine;
  line_length_ = 0;
  line_is_range_ = true;
  line_name_.clear();
  in_value_ = literal_value_ = percent_encoded_ = headers_too_large_ = false;
}

void ConnectionStream::at_colon() {
  in_value_ = true;
  literal_value_ = false;
  for (const std::string& name : literal_headers_) literal_value_ = literal_value_ || line_name_ == name;
}

bool ConnectionStream::admit(char c) {
  if (part_ == Part::kBody) return true;
  if (c == '\n') {
    // httplib ends the headers at a line of exactly "\r\n" (and skips a line ending in a bare '\n').
    if (part_ == Part::kHeaders && line_length_ == 1 && line_starts_cr_) part_ = Part::kBody;
    if (part_ == Part::kRequestLine) part_ = Part::kHeaders;
    line_length_ = 0;
    line_is_range_ = true;
    line_name_.clear();
    in_value_ = literal_value_ = false;
    return true;
  }
  if (line_length_ == 0) line_starts_cr_ = c == '\r';
  if (part_ == Part::kHeaders) {
    static constexpr char kRange[] = "range:";
    if (line_is_range_ && line_length_ < 6) {
      line_is_range_ = std::tolower(static_cast<unsigned char>(c)) == kRange[line_length_];
      if (line_is_range_ && line_length_ == 5) {
        range_refused_ = true;
        return false;
      }
    }
    if (in_value_) {
      percent_encoded_ = percent_encoded_ || (literal_value_ && c == '%');
    } else if (c == ':') {
      at_colon();
    } else if (line_name_.size() <= kMaxNameBytes) {
      line_name_ += char(std::tolower(static_cast<unsigned char>(c)));
    }
  }
  ++line_length_;
  // httplib refuses a header line (with its "\r\n") longer than this, as a malformed request.
  if (part_ == Part::kHeaders && line_length_ + 1 > CPPHTTPLIB_HEADER_MAX_LENGTH) headers_too_large_ = true;
  return true;
}

bool ConnectionStream::wait(short events, Clock::time_point deadline) const {
  for (;;) {
    const Clock::time_point now = now_();
    if (now >= deadline) {
      timed_out_ = true;
      return false;
    }
    if (stopping_.load()) {
      // A request is not awaited; a response gets a short grace to be taken.
      if (stop_seen_ == Clock::time_point{}) stop_seen_ = now;
      if (events != POLLOUT || now >= stop_seen_ + kStopGrace) return false;
    }
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
  return wait(POLLOUT, writing_ ? write_deadline_ : now_() + limits_.response_time);
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
  if (range_refused_) return -1;
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
  const size_t n = std::min(size, len_ - pos_);
  size_t admitted = 0;
  while (admitted < n && admit(buffer_[pos_ + admitted])) ++admitted;
  if (admitted == 0 && range_refused_) return -1;  // the colon of a Range header
  std::memcpy(ptr, buffer_ + pos_, admitted);
  pos_ += admitted;
  return ssize_t(admitted);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
  if (!writing_) {
    writing_ = true;
    write_deadline_ = now_() + limits_.response_time;
    if (on_response_) on_response_();
  }
  if (expect_head_) {
    // httplib writes a response's status line and headers in one piece.
    expect_head_ = false;
    const std::string_view data(ptr, size);
    if (data.starts_with("HTTP/1.") && data.ends_with("\r\n\r\n")) {
      expect_head_ = data.size() > 9 && data[9] == '1';  // "100 Continue": the response's own head follows
      if (head_closes_connection(data)) return send_all(closing_head(data)) ? ssize_t(size) : -1;
    }
  }
  if (!wait(POLLOUT, write_deadline_)) return -1;
  ssize_t n;
  do { n = send(fd_, ptr, size, MSG_NOSIGNAL); } while (n < 0 && errno == EINTR);
  if (n > 0) wrote_ = true;
  return n;
}

bool ConnectionStream::send_all(const std::string& bytes) {
  for (size_t done = 0; done < bytes.size();) {
    if (!wait(POLLOUT, write_deadline_)) return false;
    ssize_t n = send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    wrote_ = true;
    done += size_t(n);
  }
  return true;
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
