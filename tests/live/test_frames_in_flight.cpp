// The frames being sent, as bookkeeping: a frame counts once however many
// responses send it, a lease past the budget names the connections sending
// the oldest other frames (never the frame being leased, which may exceed the
// budget alone), and a frame counts until its last response is done or cut.
// The memory it bounds is measured by tests/live/test_live_memory.cpp.
#include <gtest/gtest.h>

#include "live/frames_in_flight.h"

namespace pt::live {
namespace {

TEST(FramesInFlight, AFrameCountsOnceAndUntilItsLastResponseIsDone) {
  FramesInFlight frames(100);
  FramesInFlight::Leased a = frames.lease(1, 60, 10), b = frames.lease(1, 60, 11);
  EXPECT_TRUE(a.cut.empty());
  EXPECT_TRUE(b.cut.empty());
  EXPECT_EQ(frames.bytes(), 60u);
  a.lease.reset();
  EXPECT_EQ(frames.bytes(), 60u);
  b.lease.reset();
  EXPECT_EQ(frames.bytes(), 0u);
}

TEST(FramesInFlight, ALeasePastTheBudgetCutsTheResponsesOfTheOldestOtherFrames) {
  FramesInFlight frames(100);
  FramesInFlight::Leased one = frames.lease(1, 40, 10), also_one = frames.lease(1, 40, 11);
  FramesInFlight::Leased two = frames.lease(2, 40, 12);
  EXPECT_TRUE(two.cut.empty());
  EXPECT_EQ(frames.bytes(), 80u);
  // Frame 3 would make 120: frame 1 goes, with both of its responses.
  FramesInFlight::Leased three = frames.lease(3, 40, 13);
  EXPECT_EQ(three.cut, (std::vector<uint64_t>{10, 11}));
  EXPECT_EQ(frames.bytes(), 80u);
  // A cut frame's responses end later; they change nothing.
  one.lease.reset();
  also_one.lease.reset();
  EXPECT_EQ(frames.bytes(), 80u);
  // A frame larger than the budget alone is leased; every other frame goes.
  FramesInFlight::Leased huge = frames.lease(4, 500, 14);
  EXPECT_EQ(huge.cut, (std::vector<uint64_t>{12, 13}));
  EXPECT_EQ(frames.bytes(), 500u);
  FramesInFlight::Leased again = frames.lease(4, 500, 15);
  EXPECT_TRUE(again.cut.empty()) << "a frame being sent costs nothing more to send again";
  huge.lease.reset();
  again.lease.reset();
  EXPECT_EQ(frames.bytes(), 0u);
}

}  // namespace
}  // namespace pt::live
