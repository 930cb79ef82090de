// A raw HTTP client for the hostile-request tests: it sends exactly the bytes
// a test writes (partial requests, trickles, garbage) over a loopback socket
// and reads whatever comes back, with time limits, so that a server which
// hangs fails the test instead of stalling it.
#pragma once

#include <chrono>
#include <string>

namespace pt::test {

/// A connected loopback socket, closed on destruction.
class Probe {
 public:
  explicit Probe(int port);
  ~Probe();
  Probe(const Probe&) = delete;
  Probe& operator=(const Probe&) = delete;
  bool connected() const { return fd_ >= 0; }
  /// Sends all of `bytes`; false if the server closed the connection.
  bool send(const std::string& bytes);
  /// Reads until the server closes the connection or `limit` passes.
  std::string read_all(std::chrono::milliseconds limit);

 private:
  int fd_ = -1;
};

/// Sends `request` on a fresh connection and reads the reply until close or `limit`.
std::string exchange(int port, const std::string& request,
                     std::chrono::milliseconds limit = std::chrono::milliseconds(5000));

/// The status code of a reply ("HTTP/1.1 404 Not Found..." -> 404), or -1.
int status_of(const std::string& reply);

}  // namespace pt::test
