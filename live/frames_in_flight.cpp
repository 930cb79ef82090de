// Leases by frame id under one mutex: a few frames at a time.
#include "frames_in_flight.h"

#include <algorithm>

namespace pt::live {

FramesInFlight::Leased FramesInFlight::lease(uint64_t frame, size_t bytes, uint64_t connection) {
  std::lock_guard lock(mutex_);
  Leased out;
  auto [it, added] = frames_.try_emplace(frame);
  if (added) {
    it->second.bytes = bytes;
    bytes_ += bytes;
  }
  it->second.connections.push_back(connection);
  // The oldest other frames go first; their responses are cut, so they no longer count.
  for (auto old = frames_.begin(); bytes_ > budget_ && old != frames_.end();) {
    if (old->first == frame) {
      ++old;
      continue;
    }
    out.cut.insert(out.cut.end(), old->second.connections.begin(), old->second.connections.end());
    bytes_ -= old->second.bytes;
    old = frames_.erase(old);
  }
  out.lease = std::make_unique<Lease>(*this, frame, connection);
  return out;
}

void FramesInFlight::release(uint64_t frame, uint64_t connection) {
  std::lock_guard lock(mutex_);
  auto it = frames_.find(frame);
  if (it == frames_.end()) return;  // cut already
  auto& c = it->second.connections;
  auto at = std::find(c.begin(), c.end(), connection);
  if (at != c.end()) c.erase(at);
  if (!c.empty()) return;
  bytes_ -= it->second.bytes;
  frames_.erase(it);
}

size_t FramesInFlight::bytes() const {
  std::lock_guard lock(mutex_);
  return bytes_;
}

}  // namespace pt::live
