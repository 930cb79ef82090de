// One HTTP connection's bytes for cpp-httplib, with the limits its own
// socket stream lacks: a request (line, headers and body) must arrive whole
// within a deadline and a byte budget, and a response must be taken by the
// client within another, however the bytes trickle in or out. A slow or
// stalled client therefore holds a server thread for a bounded time.
// The stream also reads the header names as httplib takes the bytes, and
// stops a request at a Range header's name: httplib would parse the header
// with std::regex before any handler runs (about 400 bytes of stack per byte
// of the header: 3 to 4 MiB for the longest header httplib takes, more than
// a thread's stack under some limits) and would then answer each of
// thousands of ranges with a copy of the body.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <string>

#include <httplib.h>

namespace pt::live {

/// 24 bytes.
struct StreamLimits {
  std::chrono::milliseconds request_time{5000};    ///< for all of a request's bytes
  std::chrono::milliseconds response_time{30000};  ///< for all of a response's bytes
  size_t request_bytes = 64 * 1024;                ///< line, headers and body of one request
};
static_assert(sizeof(StreamLimits) == 24);

class ConnectionStream final : public httplib::Stream {
 public:
  using Clock = std::chrono::steady_clock;

  /// How long a response may still be written once the server stops.
  static constexpr std::chrono::milliseconds kStopGrace{1000};

  /// `stopping` is polled while waiting: once it is set, reads fail at once and
  /// writes within kStopGrace, so that a stopping server is not held up.
  ConnectionStream(int fd, const StreamLimits& limits, const std::atomic<bool>& stopping);

  /// The next request starts now: fresh deadlines and byte budget.
  void begin_request();
  /// Bytes of the next request already read (pipelined behind the last one).
  bool has_buffered() const { return pos_ < len_; }
  bool timed_out() const { return timed_out_; }
  bool too_large() const { return too_large_; }
  bool wrote() const { return wrote_; }
  /// The request had a Range header: its bytes stopped before the header's colon (httplib then fails to read
  /// the headers and answers 400, which the server turns into 416); the rest of the connection is unread.
  bool range_refused() const { return range_refused_; }

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return fd_; }

 private:
  /// Polls for `events` until `deadline` (in slices, watching the stop flag); false on timeout or error.
  bool wait(short events, Clock::time_point deadline) const;
  /// Follows the request's lines byte by byte; false at the colon of a Range header.
  bool admit(char c);

  int fd_;
  StreamLimits limits_;
  const std::atomic<bool>& stopping_;
  mutable Clock::time_point stop_seen_{};  ///< when a wait first saw the stop flag (epoch: not yet)
  Clock::time_point read_deadline_, write_deadline_;
  size_t request_bytes_ = 0;
  char buffer_[4096];
  size_t pos_ = 0, len_ = 0;
  mutable bool timed_out_ = false;
  bool too_large_ = false, wrote_ = false, writing_ = false;
  // Where the request's bytes are: its line, its headers, or past the blank line that ends them.
  enum class Part : uint8_t { kRequestLine, kHeaders, kBody } part_ = Part::kRequestLine;
  size_t line_length_ = 0;     ///< bytes of the current line before its '\n'
  bool line_is_range_ = true;  ///< the current line so far is a prefix of "range:" (any case)
  bool line_starts_cr_ = false;
  bool range_refused_ = false;
};

}  // namespace pt::live
