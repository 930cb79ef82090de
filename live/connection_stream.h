// One HTTP connection's bytes for cpp-httplib, with the limits its own
// socket stream lacks: a request (line, headers and body) must arrive whole
// within a deadline and a byte budget, and a response must be taken by the
// client within another, however the bytes trickle in or out. A slow or
// stalled client therefore holds a server thread for a bounded time.
#pragma once

#include <sys/types.h>

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

  /// `running` is polled while waiting, so that a stopping server is not held up.
  ConnectionStream(int fd, const StreamLimits& limits, const httplib::Server& server);

  /// The next request starts now: fresh deadlines and byte budget.
  void begin_request();
  /// Bytes of the next request already read (pipelined behind the last one).
  bool has_buffered() const { return pos_ < len_; }
  bool timed_out() const { return timed_out_; }
  bool too_large() const { return too_large_; }
  bool wrote() const { return wrote_; }

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return fd_; }

 private:
  /// Polls for `events` until `deadline` (in slices, watching the server); false on timeout or error.
  bool wait(short events, Clock::time_point deadline) const;

  int fd_;
  StreamLimits limits_;
  const httplib::Server& server_;
  Clock::time_point read_deadline_, write_deadline_;
  size_t request_bytes_ = 0;
  char buffer_[4096];
  size_t pos_ = 0, len_ = 0;
  mutable bool timed_out_ = false;
  bool too_large_ = false, wrote_ = false, writing_ = false;
};

}  // namespace pt::live
