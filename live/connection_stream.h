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
// thousands of ranges with a copy of the body. It notes the headers whose
// values must arrive literally but came percent-encoded (httplib decodes
// every header value), and headers too long for httplib (431, not 400). A
// response's head goes out with one Connection header (response_head.h).
// Its deadlines are on a clock the server gives (a test's, or steady_clock).
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <httplib.h>

namespace pt::live {

/// 24 bytes.
struct StreamLimits {
  std::chrono::milliseconds request_time{5000};    ///< for all of a request's bytes
  std::chrono::milliseconds response_time{30000};  ///< for all of a response's bytes
  size_t request_bytes = 64 * 1024;                ///< line, headers and body of one request
};
static_assert(sizeof(StreamLimits) == 24);

/// The clock of the server's deadlines: steady_clock's time, or a test's.
using Clock = std::chrono::steady_clock;
using NowFunction = std::function<Clock::time_point()>;

class ConnectionStream final : public httplib::Stream {
 public:
  /// How long a response may still be written once the server stops.
  static constexpr std::chrono::milliseconds kStopGrace{1000};
  /// How often a wait looks at the stop flag and the clock (the clock may be a test's, which jumps).
  static constexpr std::chrono::milliseconds kSlice{100};

  /// `stopping` is polled while waiting: once it is set, reads fail at once and
  /// writes within kStopGrace, so that a stopping server is not held up. `literal_headers` are the names (lower
  /// case) whose values percent_encoded() reports; `now` and `literal_headers` outlive the stream.
  ConnectionStream(int fd, const StreamLimits& limits, const std::atomic<bool>& stopping, const NowFunction& now,
                   const std::vector<std::string>& literal_headers);

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
  /// A header line was longer than httplib takes, or the request's bytes ran out before its headers ended.
  bool headers_too_large() const { return headers_too_large_ || (too_large_ && part_ != Part::kBody); }
  /// The request line alone ran out of the request's bytes.
  bool line_too_large() const { return too_large_ && part_ == Part::kRequestLine; }
  /// A header of `literal_headers` had a '%' in its value (httplib hands the handlers its value decoded).
  bool percent_encoded() const { return percent_encoded_; }
  /// Called at the first byte of each response (the server's handler has finished).
  void set_on_response(std::function<void()> on_response) { on_response_ = std::move(on_response); }

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
  /// At a header's colon: what the name so far says about the value that follows.
  void at_colon();
  /// Sends all of `bytes` (false when the client is gone or the deadline passes).
  bool send_all(const std::string& bytes);

  int fd_;
  StreamLimits limits_;
  const std::atomic<bool>& stopping_;
  const NowFunction& now_;
  const std::vector<std::string>& literal_headers_;
  std::function<void()> on_response_;
  mutable Clock::time_point stop_seen_{};  ///< when a wait first saw the stop flag (epoch: not yet)
  Clock::time_point read_deadline_, write_deadline_;
  size_t request_bytes_ = 0;
  char buffer_[4096];
  size_t pos_ = 0, len_ = 0;
  mutable bool timed_out_ = false;
  bool too_large_ = false, wrote_ = false, writing_ = false;
  bool expect_head_ = true;  ///< the next write starts a response's head
  // Where the request's bytes are: its line, its headers, or past the blank line that ends them.
  enum class Part : uint8_t { kRequestLine, kHeaders, kBody } part_ = Part::kRequestLine;
  size_t line_length_ = 0;     ///< bytes of the current line before its '\n'
  bool line_is_range_ = true;  ///< the current line so far is a prefix of "range:" (any case)
  bool line_starts_cr_ = false;
  bool range_refused_ = false;
  std::string line_name_;           ///< the current header line's name so far, in lower case (up to 32 bytes)
  bool in_value_ = false;           ///< past the current header line's colon
  bool literal_value_ = false;      ///< the current header is one of literal_headers_
  bool percent_encoded_ = false;    ///< a literal header's value had a '%'
  bool headers_too_large_ = false;  ///< a header line longer than httplib's CPPHTTPLIB_HEADER_MAX_LENGTH
};

}  // namespace pt::live
