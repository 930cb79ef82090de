// Who holds the server's connections, doing what since when: each client (an
// address) has a share, so that one client, or a few, cannot take every
// connection from the others. A client holds at most `per_client`
// connections and `frame_waits_per_client` frame requests waiting at once.
// When all `connections` are taken, a new connection from a client that
// holds fewer than another client by two or more takes one of that client's
// connections: the heaviest client's, one that waits for a request or writes
// a response (never one whose handler runs), the idle ones first. So each of
// n clients keeps at least connections / n of them, as long as the others'
// handlers (frame waits, at most frame_waits_per_client per client) leave
// room. A phase that outlasts its limit ends its connection. Bookkeeping
// only: a connection's `evict` closes its socket, called under the lock.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace pt::live {

struct ShareLimits {
  size_t connections = 48;  ///< open at once, in all
  size_t per_client = 16;   ///< open at once from one client
  /// frame requests waiting at once from one client: as many as the connections a browser opens to one server
  /// (six), so that a browser's tabs, each waiting for its next frame, are never refused
  size_t frame_waits_per_client = 6;
};

/// The client an address counts as: an IPv4 address itself (also written as an IPv4-mapped IPv6 address),
/// an IPv6 address by its /64 prefix (one host usually holds a whole /64), as "2001:db8:0:1::/64".
std::string client_of(const std::string& ip);

class ClientShares {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  /// What a connection is doing. Only kHandling (a route's handler runs, a frame request waits) protects
  /// it from being taken by another client, and has no time limit.
  enum class Phase : uint8_t { kIdle, kReading, kHandling, kWriting };
  enum class Refusal : uint8_t { kNone, kClientFull, kServerFull };
  /// 24 bytes. How long each phase may last; kHandling has no limit.
  struct PhaseLimits {
    std::chrono::milliseconds idle, reading, writing;
  };

  struct Admission {
    Refusal refusal = Refusal::kNone;
    uint64_t id = 0;             ///< the connection's id (refusal kNone)
    size_t held = 0;             ///< connections the client holds, this one included (or, refused, already)
    std::string evicted_client;  ///< whose connection this one took ("" when none)
  };
  /// A connection ended by its phase's limit.
  struct Overdue {
    std::string peer;
    Phase phase;
  };

  explicit ClientShares(const ShareLimits& limits) : limits_(limits) {}

  /// Admits a connection of `client` (from `peer`, "address:port") in phase kIdle since `now`, or refuses it.
  /// To admit it, another client's connection may be taken: its `evict` is called and it no longer counts.
  Admission admit(const std::string& client, const std::string& peer, std::function<void()> evict, TimePoint now);
  void set_phase(uint64_t id, Phase phase, TimePoint now);
  /// The connection closed (its socket may be closed once this returns: `evict` is never called after).
  void leave(uint64_t id);
  /// Ends a connection now (its `evict`); false if it had left.
  bool end(uint64_t id);
  /// Ends the connections whose phase has lasted longer than `limits` allow at `now`.
  std::vector<Overdue> end_overdue(TimePoint now, const PhaseLimits& limits);
  /// Whether `client` may have one more frame request waiting; if so it counts until end_frame_wait.
  bool begin_frame_wait(const std::string& client);
  void end_frame_wait(const std::string& client);

  size_t open() const;
  /// Connections in `phase` now.
  size_t in_phase(Phase phase) const;
  size_t held_by(const std::string& client) const;
  size_t frame_waits() const;
  const ShareLimits& limits() const { return limits_; }

 private:
  struct Connection {
    std::string client, peer;
    Phase phase = Phase::kIdle;
    TimePoint since;
    std::function<void()> evict;
  };
  /// Under the lock: calls the connection's evict and counts it out.
  void drop(std::map<uint64_t, Connection>::iterator it);

  ShareLimits limits_;
  mutable std::mutex mutex_;
  std::map<uint64_t, Connection> connections_;  ///< by id: in the order admitted
  std::map<std::string, size_t> held_;          ///< connections per client (no zero entries)
  std::map<std::string, size_t> waits_;         ///< frame waits per client (no zero entries)
  size_t total_waits_ = 0;
  uint64_t next_id_ = 1;
};

/// One frame request's place among its client's waiting ones, given back on destruction.
class FrameWait {
 public:
  FrameWait(ClientShares& shares, std::string client)
      : shares_(shares), client_(std::move(client)), granted_(shares_.begin_frame_wait(client_)) {}
  ~FrameWait() {
    if (granted_) shares_.end_frame_wait(client_);
  }
  FrameWait(const FrameWait&) = delete;
  FrameWait& operator=(const FrameWait&) = delete;
  /// False: the client has frame_waits_per_client requests waiting already.
  explicit operator bool() const { return granted_; }

 private:
  ClientShares& shares_;
  std::string client_;
  bool granted_;
};

}  // namespace pt::live
