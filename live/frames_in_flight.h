// The frames that responses are sending, within a budget of bytes. A frame
// response leases its frame for as long as it is sent; a frame counts once
// however many responses send it. A lease that takes the frames past the
// budget names the connections sending the oldest other frames, to be cut
// until the rest fits (the newest frame alone may exceed it). So clients that
// read their frames slowly or never hold at most the budget (and the frame
// being leased) however many they are. Bookkeeping only: the caller cuts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace pt::live {

class FramesInFlight {
 public:
  explicit FramesInFlight(size_t budget) : budget_(budget) {}

  /// A response's hold on its frame, given back on destruction. The FramesInFlight outlives it.
  class Lease {
   public:
    Lease(FramesInFlight& owner, uint64_t frame, uint64_t connection)
        : owner_(owner), frame_(frame), connection_(connection) {}
    ~Lease() { owner_.release(frame_, connection_); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;

   private:
    FramesInFlight& owner_;
    uint64_t frame_, connection_;
  };
  struct Leased {
    std::unique_ptr<Lease> lease;
    std::vector<uint64_t> cut;  ///< connections to close: they send frames beyond the budget
  };

  /// Leases frame `frame` (ids grow with time) of `bytes` for the response on `connection`.
  Leased lease(uint64_t frame, size_t bytes, uint64_t connection);
  /// The bytes of the frames leased now.
  size_t bytes() const;

 private:
  void release(uint64_t frame, uint64_t connection);

  struct Entry {
    size_t bytes = 0;
    std::vector<uint64_t> connections;  ///< one entry per lease
  };
  const size_t budget_;
  mutable std::mutex mutex_;
  std::map<uint64_t, Entry> frames_;  ///< by id: the oldest first
  size_t bytes_ = 0;
};

}  // namespace pt::live
