// The shares under one mutex: a few dozen connections, scanned whole when
// the server is full and for the deadlines.
#include "client_shares.h"

#include <arpa/inet.h>

#include <cstring>

namespace pt::live {

std::string client_of(const std::string& ip) {
  in6_addr a{};
  if (inet_pton(AF_INET6, ip.c_str(), &a) != 1) return ip;  // IPv4, or not an address: as it is
  static constexpr unsigned char kMapped[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
  char text[INET6_ADDRSTRLEN] = "";
  if (std::memcmp(a.s6_addr, kMapped, sizeof kMapped) == 0) {
    inet_ntop(AF_INET, a.s6_addr + 12, text, sizeof text);
    return text;
  }
  std::memset(a.s6_addr + 8, 0, 8);
  inet_ntop(AF_INET6, &a, text, sizeof text);
  return std::string(text) + "/64";
}

namespace {

/// Which of a client's connections is taken first: the idle ones, then those reading a request, then writing.
int eviction_rank(ClientShares::Phase phase) {
  switch (phase) {
    case ClientShares::Phase::kIdle: return 0;
    case ClientShares::Phase::kReading: return 1;
    default: return 2;
  }
}

size_t count_of(const std::map<std::string, size_t>& counts, const std::string& client) {
  auto it = counts.find(client);
  return it == counts.end() ? 0 : it->second;
}

void decrement(std::map<std::string, size_t>& counts, const std::string& client) {
  auto it = counts.find(client);
  if (it != counts.end() && --it->second == 0) counts.erase(it);
}

}  // namespace

ClientShares::Admission ClientShares::admit(const std::string& client, const std::string& peer,
                                            std::function<void()> evict, TimePoint now) {
  std::lock_guard lock(mutex_);
  Admission out;
  const size_t held = count_of(held_, client);
  out.held = held;
  if (held >= limits_.per_client) {
    out.refusal = Refusal::kClientFull;
    return out;
  }
  if (connections_.size() >= limits_.connections) {
    // The connection to take: of the client holding the most (at least two more than this one, so that
    // taking it evens the shares), not in a handler, idle before reading before writing, the oldest.
    auto taken = connections_.end();
    size_t taken_held = 0;
    for (auto it = connections_.begin(); it != connections_.end(); ++it) {
      const Connection& c = it->second;
      if (c.phase == Phase::kHandling || c.client == client) continue;
      const size_t h = count_of(held_, c.client);
      if (h < held + 2) continue;
      if (taken == connections_.end() || h > taken_held ||
          (h == taken_held && eviction_rank(c.phase) < eviction_rank(taken->second.phase))) {
        taken = it;
        taken_held = h;
      }
    }
    if (taken == connections_.end()) {
      out.refusal = Refusal::kServerFull;
      return out;
    }
    out.evicted_client = taken->second.client;
    drop(taken);
  }
  out.id = next_id_++;
  connections_.emplace(out.id, Connection{client, peer, Phase::kIdle, now, std::move(evict)});
  out.held = ++held_[client];
  return out;
}

void ClientShares::drop(std::map<uint64_t, Connection>::iterator it) {
  if (it->second.evict) it->second.evict();
  decrement(held_, it->second.client);
  connections_.erase(it);
}

void ClientShares::set_phase(uint64_t id, Phase phase, TimePoint now) {
  std::lock_guard lock(mutex_);
  auto it = connections_.find(id);
  if (it == connections_.end()) return;
  it->second.phase = phase;
  it->second.since = now;
}

void ClientShares::leave(uint64_t id) {
  std::lock_guard lock(mutex_);
  auto it = connections_.find(id);
  if (it == connections_.end()) return;  // taken by another client or ended: counted out already
  decrement(held_, it->second.client);
  connections_.erase(it);
}

bool ClientShares::end(uint64_t id) {
  std::lock_guard lock(mutex_);
  auto it = connections_.find(id);
  if (it == connections_.end()) return false;
  drop(it);
  return true;
}

std::vector<ClientShares::Overdue> ClientShares::end_overdue(TimePoint now, const PhaseLimits& limits) {
  std::lock_guard lock(mutex_);
  std::vector<Overdue> out;
  for (auto it = connections_.begin(); it != connections_.end();) {
    const Connection& c = it->second;
    const std::chrono::milliseconds limit = c.phase == Phase::kIdle      ? limits.idle
                                            : c.phase == Phase::kReading ? limits.reading
                                                                         : limits.writing;
    if (c.phase == Phase::kHandling || now - c.since <= limit) {
      ++it;
      continue;
    }
    out.push_back({c.peer, c.phase});
    drop(it++);
  }
  return out;
}

bool ClientShares::begin_frame_wait(const std::string& client) {
  std::lock_guard lock(mutex_);
  size_t& n = waits_[client];
  if (n >= limits_.frame_waits_per_client) {
    if (n == 0) waits_.erase(client);
    return false;
  }
  ++n;
  ++total_waits_;
  return true;
}

void ClientShares::end_frame_wait(const std::string& client) {
  std::lock_guard lock(mutex_);
  decrement(waits_, client);
  --total_waits_;
}

size_t ClientShares::open() const {
  std::lock_guard lock(mutex_);
  return connections_.size();
}

size_t ClientShares::in_phase(Phase phase) const {
  std::lock_guard lock(mutex_);
  size_t n = 0;
  for (const auto& [id, c] : connections_) n += c.phase == phase;
  return n;
}

size_t ClientShares::held_by(const std::string& client) const {
  std::lock_guard lock(mutex_);
  return count_of(held_, client);
}

size_t ClientShares::frame_waits() const {
  std::lock_guard lock(mutex_);
  return total_waits_;
}

}  // namespace pt::live
