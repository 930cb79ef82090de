// Probe on a blocking socket read with poll() deadlines.
#include "support/http_probe.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <thread>

namespace pt::test {

Probe::Probe(int port, const std::string& from) {
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  if (fd_ >= 0 && (inet_pton(AF_INET, from.c_str(), &local.sin_addr) != 1 ||
                   bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0)) {
    close(fd_);
    fd_ = -1;
  }
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(uint16_t(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd_ >= 0 && connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    close(fd_);
    fd_ = -1;
  }
}

Probe::~Probe() {
  if (fd_ >= 0) close(fd_);
}

bool Probe::send(const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += size_t(n);
  }
  return true;
}

std::string Probe::read_all(std::chrono::milliseconds limit) {
  std::string out;
  const auto deadline = std::chrono::steady_clock::now() + limit;
  char buf[65536];
  for (;;) {
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return out;
    pollfd p{fd_, POLLIN, 0};
    int r = poll(&p, 1, int(left.count()));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return out;
    ssize_t n = recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) return out;
    out.append(buf, size_t(n));
  }
}

std::string Probe::read_response(std::chrono::milliseconds limit) {
  std::string out;
  const auto deadline = std::chrono::steady_clock::now() + limit;
  char buf[65536];
  for (;;) {
    const size_t head = out.find("\r\n\r\n");
    if (head != std::string::npos) {
      std::vector<std::string> lengths = header_values(out, "Content-Length");
      const size_t body = lengths.empty() ? 0 : size_t(std::atoll(lengths[0].c_str()));
      if (out.size() >= head + 4 + body) return out;
    }
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return out;
    pollfd p{fd_, POLLIN, 0};
    int r = poll(&p, 1, int(left.count()));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return out;
    ssize_t n = recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) return out;
    out.append(buf, size_t(n));
  }
}

std::string exchange(int port, const std::string& request, std::chrono::milliseconds limit, const std::string& from) {
  Probe p(port, from);
  if (!p.connected() || !p.send(request)) return {};
  return p.read_all(limit);
}

bool wait_until(const std::function<bool()>& condition, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!condition()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

int status_of(const std::string& reply) {
  if (reply.rfind("HTTP/1.", 0) != 0 || reply.size() < 12) return -1;
  return std::atoi(reply.c_str() + 9);
}

std::string body_of(const std::string& reply) {
  const size_t head = reply.find("\r\n\r\n");
  return head == std::string::npos ? std::string() : reply.substr(head + 4);
}

std::vector<std::string> header_values(const std::string& reply, const std::string& name) {
  std::vector<std::string> out;
  const size_t end = reply.find("\r\n\r\n");
  size_t at = reply.find("\r\n");
  while (at != std::string::npos && at < end) {
    const size_t next = reply.find("\r\n", at + 2);
    const std::string line = reply.substr(at + 2, next - at - 2);
    const size_t colon = line.find(':');
    if (colon == name.size() && strncasecmp(line.c_str(), name.c_str(), name.size()) == 0) {
      size_t from = line.find_first_not_of(" \t", colon + 1);
      out.push_back(from == std::string::npos ? std::string() : line.substr(from));
    }
    at = next;
  }
  return out;
}

}  // namespace pt::test
