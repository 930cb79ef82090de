// The clients' shares of the server's connections, as bookkeeping: a
// client's cap, a full server that admits a client below its share by
// taking a connection of the heaviest client (never one whose handler runs,
// idle ones first), frame waits per client, the limit of each phase, and the
// address a client counts as. The server under attack is
// tests/live/test_live_server.cpp.
#include <gtest/gtest.h>

#include "live/client_shares.h"

namespace pt::live {
namespace {

using Phase = ClientShares::Phase;
using Refusal = ClientShares::Refusal;
using std::chrono::milliseconds;
const ClientShares::TimePoint kT0{};

/// Admits a connection of `client` that records its eviction in `evicted` (by the order it was admitted in).
uint64_t admit(ClientShares& shares, const std::string& client, std::vector<int>& evicted, int index) {
  ClientShares::Admission a = shares.admit(
      client, client + ":1", [&evicted, index] { evicted.push_back(index); }, kT0);
  EXPECT_EQ(a.refusal, Refusal::kNone) << client;
  return a.id;
}

TEST(ClientShares, AClientHoldsAtMostItsShare) {
  ClientShares shares({.connections = 10, .per_client = 3, .frame_waits_per_client = 1});
  std::vector<int> evicted;
  for (int i = 0; i < 3; ++i) admit(shares, "a", evicted, i);
  ClientShares::Admission fourth = shares.admit("a", "peer", {}, kT0);
  EXPECT_EQ(fourth.refusal, Refusal::kClientFull);
  EXPECT_EQ(fourth.held, 3u);
  EXPECT_EQ(shares.admit("b", "peer", {}, kT0).refusal, Refusal::kNone);
  EXPECT_EQ(shares.open(), 4u);
  EXPECT_TRUE(evicted.empty());
}

TEST(ClientShares, AFullServerGivesAClientBelowItsShareAConnectionOfTheHeaviestClient) {
  ClientShares shares({.connections = 6, .per_client = 6, .frame_waits_per_client = 1});
  std::vector<int> evicted;
  std::vector<uint64_t> a;
  for (int i = 0; i < 4; ++i) a.push_back(admit(shares, "a", evicted, i));
  const uint64_t b0 = admit(shares, "b", evicted, 10), b1 = admit(shares, "b", evicted, 11);
  // Phases: a's first handles a request, its second writes, its third reads, its fourth is idle.
  shares.set_phase(a[0], Phase::kHandling, kT0);
  shares.set_phase(a[1], Phase::kWriting, kT0);
  shares.set_phase(a[2], Phase::kReading, kT0);
  ClientShares::Admission c = shares.admit("c", "peer", {}, kT0);
  EXPECT_EQ(c.refusal, Refusal::kNone);
  EXPECT_EQ(c.evicted_client, "a");
  EXPECT_EQ(evicted, std::vector<int>{3}) << "the idle connection first";
  EXPECT_EQ(shares.held_by("a"), 3u);
  EXPECT_EQ(shares.open(), 6u);
  ClientShares::Admission c2 = shares.admit("c", "peer", {}, kT0);
  EXPECT_EQ(c2.evicted_client, "a");
  EXPECT_EQ(evicted, (std::vector<int>{3, 2})) << "then the one reading a request";
  // a, b and c hold 2 each: a third for c would take from a client holding 4.
  EXPECT_EQ(shares.admit("c", "peer", {}, kT0).refusal, Refusal::kServerFull);
  // A connection whose handler runs is never taken: with every connection in its handler, d is refused.
  for (uint64_t id : {a[1], b0, b1, c.id, c2.id}) shares.set_phase(id, Phase::kHandling, kT0);
  EXPECT_EQ(shares.admit("d", "peer", {}, kT0).refusal, Refusal::kServerFull);
  EXPECT_EQ(evicted, (std::vector<int>{3, 2}));
  // A connection taken no longer counts: its leave() changes nothing.
  shares.leave(a[3]);
  EXPECT_EQ(shares.open(), 6u);
  shares.leave(a[0]);
  EXPECT_EQ(shares.open(), 5u);
  EXPECT_EQ(shares.held_by("a"), 1u);
}

TEST(ClientShares, TakingAConnectionEvensTheSharesAndStops) {
  // Clients arriving one by one at a full server end with shares that differ by at most one.
  ClientShares shares({.connections = 12, .per_client = 12, .frame_waits_per_client = 1});
  std::vector<int> evicted;
  for (int i = 0; i < 12; ++i) admit(shares, "heavy", evicted, i);
  for (const char* client : {"b", "c", "d"})
    while (shares.admit(client, "peer", {}, kT0).refusal == Refusal::kNone) {}
  for (const char* client : {"heavy", "b", "c", "d"}) EXPECT_EQ(shares.held_by(client), 3u) << client;
  EXPECT_EQ(evicted.size(), 9u);
}

TEST(ClientShares, APhaseThatOutlastsItsLimitEndsItsConnection) {
  ClientShares shares({.connections = 8, .per_client = 8, .frame_waits_per_client = 1});
  std::vector<int> evicted;
  admit(shares, "a", evicted, 0);  // idle since it opened
  const uint64_t reading = admit(shares, "a", evicted, 1);
  const uint64_t handling = admit(shares, "a", evicted, 2), writing = admit(shares, "a", evicted, 3);
  shares.set_phase(reading, Phase::kReading, kT0 + milliseconds(100));
  shares.set_phase(handling, Phase::kHandling, kT0);
  shares.set_phase(writing, Phase::kWriting, kT0 + milliseconds(100));
  const ClientShares::PhaseLimits limits{milliseconds(1000), milliseconds(400), milliseconds(3000)};
  EXPECT_TRUE(shares.end_overdue(kT0 + milliseconds(500), limits).empty()) << "every limit is inclusive";
  std::vector<ClientShares::Overdue> ended = shares.end_overdue(kT0 + milliseconds(501), limits);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].phase, Phase::kReading);
  EXPECT_EQ(ended[0].peer, "a:1");
  EXPECT_EQ(evicted, std::vector<int>{1});
  ended = shares.end_overdue(kT0 + std::chrono::hours(1), limits);
  EXPECT_EQ(ended.size(), 2u) << "the idle and the writing connection; a handler has no limit";
  EXPECT_EQ(evicted, (std::vector<int>{1, 0, 3}));
  EXPECT_EQ(shares.open(), 1u);
  // A connection ended on request (a response cut) is evicted once; then it has left.
  EXPECT_TRUE(shares.end(handling));
  EXPECT_FALSE(shares.end(handling));
  EXPECT_EQ(evicted, (std::vector<int>{1, 0, 3, 2}));
  EXPECT_EQ(shares.held_by("a"), 0u);
}

TEST(ClientShares, FrameWaitsArePerClient) {
  ClientShares shares({.connections = 4, .per_client = 4, .frame_waits_per_client = 2});
  {
    FrameWait one(shares, "a"), two(shares, "a"), three(shares, "a"), other(shares, "b");
    EXPECT_TRUE(one);
    EXPECT_TRUE(two);
    EXPECT_FALSE(three);
    EXPECT_TRUE(other);
    EXPECT_EQ(shares.frame_waits(), 3u);
  }
  EXPECT_EQ(shares.frame_waits(), 0u);
  FrameWait again(shares, "a");
  EXPECT_TRUE(again);
}

TEST(ClientShares, AnAddressCountsAsItsIpv4AddressOrItsIpv6Slash64) {
  EXPECT_EQ(client_of("127.0.0.2"), "127.0.0.2");
  EXPECT_EQ(client_of("::ffff:192.0.2.7"), "192.0.2.7");
  EXPECT_EQ(client_of("2001:db8:0:1:aaaa:bbbb:cccc:dddd"), "2001:db8:0:1::/64");
  EXPECT_EQ(client_of("2001:db8:0:1::9"), client_of("2001:db8:0:1:ffff::1"));
  EXPECT_NE(client_of("2001:db8:0:1::9"), client_of("2001:db8:0:2::9"));
  EXPECT_EQ(client_of("::1"), "::/64");
}

}  // namespace
}  // namespace pt::live
