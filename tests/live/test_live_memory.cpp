// Memory bounded whatever clients do: 48 clients that each ask for a frame of
// a 1024x1024 view, each a frame of its own, and never read it add at most
// 64 MiB to the server's peak resident memory (the frames being sent are
// bounded: live/frames_in_flight.h; without the bound each reader holds its
// frame's 4 MiB of pixels). Measured as the process's peak resident set
// (VmHWM, reset before each run) over 48 moves whose frames a client reads,
// then over 48 moves whose frames 48 clients never read: the render's own
// peak (its accumulators, about 120 bytes a pixel) is in both.
#include <fstream>
#include <sstream>

#include "live_server_fixture.h"

namespace pt::live {
namespace {

using namespace test_server;

/// A field of /proc/self/status ("VmRSS", "VmHWM"), in bytes.
size_t status_bytes(const std::string& field) {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind(field + ":", 0) == 0) return size_t(std::stoull(line.substr(field.size() + 1))) << 10;
  ADD_FAILURE() << field << " is not in /proc/self/status";
  return 0;
}

class LiveServerAt1024 : public LiveServerBase {
 protected:
  // One sample of normal shading a view: each move is one frame, and a cheap one.
  LiveServerAt1024() : LiveServerBase({ServerLimits{}, 1024, 1024, 1, Display::kNormals}) {}

  /// The peak resident set over 48 moves, each frame read whole by a client, or asked for by a client of its
  /// own (from three addresses) that never reads it; those clients are left in `readers`.
  size_t peak_over_48_moves(std::vector<std::unique_ptr<test::Probe>>* readers) {
    { std::ofstream("/proc/self/clear_refs") << "5"; }  // the peak starts again from the resident set now
    for (int i = 0; i < 48; ++i) {
      EXPECT_EQ(POST("/api/nav?op=orbit&dx=1&dy=0").status(), 200);  // a new view: a frame of its own
      const std::string target = "/api/frame?after=" + std::to_string(last);
      if (readers) {
        readers->push_back(std::make_unique<test::Probe>(port, "127.0.0." + std::to_string(2 + i % 3)));
        EXPECT_TRUE(readers->back()->send("GET " + target + " HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n\r\n"));
      } else {
        EXPECT_EQ(GET(target).status(), 200);
      }
      // The wait is over once the reply (the moved view's frame) is under way.
      std::shared_ptr<const Frame> sent = session.frame_after(last, milliseconds(60000));
      EXPECT_TRUE(sent);
      last = sent ? sent->info.id : last;
      EXPECT_TRUE(test::wait_until([this] { return server.shares().frame_waits() == 0; }));
    }
    return status_bytes("VmHWM");
  }

  uint64_t last = 0;  ///< the newest frame's id
};

TEST_F(LiveServerAt1024, FortyEightReadersThatNeverReadAddAtMost64MiBToThePeakResidentMemory) {
#if PT_ADDRESS_SANITIZER
  GTEST_SKIP() << "AddressSanitizer keeps freed memory in quarantine: the resident set does not measure what the "
                  "server holds";
#endif
  last = frame_meta(GET("/api/frame?after=0").body())["id"];
  ASSERT_GT(last, 0u);
  const size_t read = peak_over_48_moves(nullptr);
  std::vector<std::unique_ptr<test::Probe>> readers;
  const size_t unread = peak_over_48_moves(&readers);
  const double added = (double(unread) - double(read)) / (1 << 20);
  std::printf(
      "    peak resident set: %.1f MiB with the frames read, %.1f MiB with 48 readers that never read "
      "(%+.1f MiB); %zu cut\n",
      double(read) / (1 << 20), double(unread) / (1 << 20), added, log_count("live: cut a connection"));
  EXPECT_LE(added, 64.0);
  // The server goes on: the frames being sent stay within the budget, and a client that reads gets its frame.
  nlohmann::json state = GET("/api/state").json();
  EXPECT_LE(state["counters"]["frame_bytes_sent"].get<size_t>(), (size_t(16) << 20) + (size_t(5) << 20));
  EXPECT_EQ(GET("/api/frame?after=0").status(), 200);
}

}  // namespace
}  // namespace pt::live
