// A raw HTTP client for the hostile-request tests: it sends exactly the bytes
// a test writes (partial requests, trickles, garbage) over a loopback socket,
// from any loopback address (so that one test can be many clients), and
// reads whatever comes back, with time limits, so that a server which hangs
// fails the test instead of stalling it.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace pt::test {

/// A connected loopback socket, closed on destruction.
class Probe {
 public:
  /// Connects to 127.0.0.1:`port` from the loopback address `from` (any of 127.0.0.0/8: a client of its own).
  explicit Probe(int port, const std::string& from = "127.0.0.1");
  ~Probe();
  Probe(const Probe&) = delete;
  Probe& operator=(const Probe&) = delete;
  bool connected() const { return fd_ >= 0; }
  /// Sends all of `bytes`; false if the server closed the connection.
  bool send(const std::string& bytes);
  /// Reads until the server closes the connection or `limit` passes.
  std::string read_all(std::chrono::milliseconds limit);
  /// Reads one response (its head and Content-Length bytes of body), leaving the connection open; what came
  /// when the server closes the connection or `limit` passes first.
  std::string read_response(std::chrono::milliseconds limit);

 private:
  int fd_ = -1;
};

/// Sends `request` on a fresh connection (from the loopback address `from`) and reads the reply until close or
/// `limit`.
std::string exchange(int port, const std::string& request,
                     std::chrono::milliseconds limit = std::chrono::milliseconds(5000),
                     const std::string& from = "127.0.0.1");

/// Waits until `condition` holds, looking every millisecond; false if `limit` passes first. The limit is a
/// timeout that ends a test whose event never comes, never the measure of a test: make it generous.
bool wait_until(const std::function<bool()>& condition, std::chrono::milliseconds limit = std::chrono::seconds(60));

/// The status code of a reply ("HTTP/1.1 404 Not Found..." -> 404), or -1.
int status_of(const std::string& reply);
/// The body of a reply (after its head), or "".
std::string body_of(const std::string& reply);
/// The values of the reply's headers named `name` (in any case), in order.
std::vector<std::string> header_values(const std::string& reply, const std::string& name);

}  // namespace pt::test
