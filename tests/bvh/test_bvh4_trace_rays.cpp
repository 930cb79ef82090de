// trace_rays, the external timing tool, on a hand-made triangle and ray file:
// one JSON line per thread count with the exact hit count and sum of t, and
// the per-ray hit file (t, primitive; misses t = tmax, 0xFFFFFFFF).
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_process.h"
#include "support/test_support.h"

namespace {

pt::test::ProcessResult run(const std::vector<std::string>& args) {
  return pt::test::run_process(PT_TRACE_RAYS, args, std::filesystem::current_path(), 120.0);
}

template <class T>
void write(const std::string& path, const std::vector<T>& data) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(T));
}

TEST(TraceRays, ReportsExactHitsAndWritesHitFile) {
  std::string dir = ::testing::TempDir();
  // Triangle 0 in the plane z = 1, triangle 1 in z = 3, both over x, y in [0, 1].
  write<float>(dir + "tris.bin", {0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 3, 1, 0, 3, 0, 1, 3});
  // ox oy oz tmin dx dy dz tmax
  write<float>(dir + "rays.bin", {0.2f, 0.2f, 0, 0, 0, 0, 1,    1e30f,   // hits triangle 0 at t = 1
                                  0.2f, 0.2f, 2, 0, 0, 0, 0.5f, 1e30f,   // hits triangle 1 at t = 2
                                  5.0f, 5.0f, 0, 0, 0, 0, 1,    7.0f});  // misses
  pt::test::ProcessResult r = run({dir + "tris.bin", dir + "rays.bin", "--threads", "2", "--hits", dir + "hits.bin"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string& out = r.out;
  ASSERT_NE(out.find("\"threads\":1,"), std::string::npos) << out;
  ASSERT_NE(out.find("\"threads\":2,"), std::string::npos) << out;
  for (const char* field :
       {"\"hits\":2,", "\"sum_t\":3,", "\"rays\":3,", "\"triangles\":2,", "\"mrays_per_s\":", "\"build_ms\":"}) {
    size_t first = out.find(field), second = out.find(field, first + 1);
    EXPECT_NE(first, std::string::npos) << field << " in " << out;
    EXPECT_NE(second, std::string::npos) << field << " twice in " << out;
  }
  std::string bytes = pt::test::file_bytes(dir + "hits.bin");
  ASSERT_EQ(bytes.size(), 3u * 8u);
  float t[3];
  uint32_t prim[3];
  for (int i = 0; i < 3; ++i) {
    std::memcpy(&t[i], &bytes[8 * i], 4);
    std::memcpy(&prim[i], &bytes[8 * i + 4], 4);
  }
  EXPECT_EQ(t[0], 1.0f);
  EXPECT_EQ(prim[0], 0u);
  EXPECT_EQ(t[1], 2.0f);
  EXPECT_EQ(prim[1], 1u);
  EXPECT_EQ(t[2], 7.0f);
  EXPECT_EQ(prim[2], 0xFFFFFFFFu);
}

/// The "method" and "hits" of every JSON line of trace_rays' output.
std::vector<std::pair<std::string, std::string>> methods_and_hits(const std::string& out) {
  std::vector<std::pair<std::string, std::string>> lines;
  for (size_t at = out.find("\"method\":\""); at != std::string::npos; at = out.find("\"method\":\"", at + 1)) {
    size_t m = at + 10, m_end = out.find('"', m);
    size_t h = out.find("\"hits\":", at) + 7, h_end = out.find(',', h);
    lines.push_back({out.substr(m, m_end - m), out.substr(h, h_end - h)});
  }
  return lines;
}

TEST(TraceRays, EveryMethodFindsTheSameHits) {
  std::string dir = ::testing::TempDir();
  write<float>(dir + "tris2.bin", {0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 3, 1, 0, 3, 0, 1, 3});
  write<float>(dir + "rays2.bin",
               {0.2f, 0.2f, 0, 0, 0, 0, 1, 1e30f, 0.2f, 0.2f, 2, 0, 0, 0, 0.5f, 1e30f,
                5.0f, 5.0f, 0, 0, 0, 0, 1, 7.0f,  0.2f, 0.2f, 0, 0, 0, 0, 1,    0.5f});  // the last stops short
  struct Run {
    std::vector<std::string> flags;
    const char* hits;  // closest hits, or blocked rays with --occluded
  };
  for (const Run& run_case : {Run{{}, "2"}, Run{{"--single"}, "2"}, Run{{"--occluded"}, "2"},
                              Run{{"--occluded", "--single"}, "2"}, Run{{"--queue", "1"}, "2"}}) {
    std::vector<std::string> args = {dir + "tris2.bin", dir + "rays2.bin", "--threads", "2"};
    args.insert(args.end(), run_case.flags.begin(), run_case.flags.end());
    pt::test::ProcessResult r = run(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto lines = methods_and_hits(r.out);
    ASSERT_EQ(lines.size(), 2u) << r.out;  // 1 and 2 threads
    for (const auto& [method, hits] : lines) EXPECT_EQ(hits, run_case.hits) << method << " in " << r.out;
  }
  pt::test::ProcessResult r = run({dir + "tris2.bin", dir + "rays2.bin", "--threads", "1", "--embree"});
  if (r.exit_code == 2 && r.err.find("no Embree") != std::string::npos) GTEST_SKIP() << "built without Embree";
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto lines = methods_and_hits(r.out);
  EXPECT_EQ(lines.size(), 1u + 2u * 11u) << r.out;  // ours, then 11 methods of each Embree build
  for (const auto& [method, hits] : lines) EXPECT_EQ(hits, "2") << method << " in " << r.out;
}

TEST(TraceRays, CountsTheWorkOfEachRay) {
  std::string dir = ::testing::TempDir();
  // Two triangles, each its own leaf under the root; four rays: one enters the
  // near leaf and stops there, one starts past it and enters the far one, one
  // misses both boxes, one stops before either.
  write<float>(dir + "tris3.bin", {0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 3, 1, 0, 3, 0, 1, 3});
  write<float>(dir + "rays3.bin", {0.2f, 0.2f, 0, 0, 0, 0, 1, 1e30f, 0.2f, 0.2f, 2, 0, 0, 0, 0.5f, 1e30f,
                                   5.0f, 5.0f, 0, 0, 0, 0, 1, 7.0f,  0.2f, 0.2f, 0, 0, 0, 0, 1,    0.5f});
  for (const char* query : {"", "--occluded"}) {
    std::vector<std::string> args = {dir + "tris3.bin", dir + "rays3.bin", "--threads", "1", "--single", "--count"};
    if (*query) args.push_back(query);
    pt::test::ProcessResult r = run(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Every ray tests the root; two rays test one triangle each.
    EXPECT_NE(r.out.find("\"method\":\"single_counts\",\"nodes_per_ray\":1.0000,\"triangles_per_ray\":0.5000}"),
              std::string::npos)
        << query << ": " << r.out;
    args.erase(args.begin() + 4);  // the queue tracer
    r = run(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The queue tracer (a stream at the levels where four rays fill a list)
    // tests the root for every ray and the two rays' triangles; a stream's
    // lists are made before the nearer hit is found, so the first ray may
    // test the far triangle as well (at most two tests for each of two rays).
    const size_t at = r.out.find("\"method\":\"queue_counts\",\"nodes_per_ray\":1.0000,\"triangles_per_ray\":");
    ASSERT_NE(at, std::string::npos) << query << ": " << r.out;
    const double triangles = std::stod(r.out.substr(r.out.find("triangles_per_ray\":", at) + 19));
    EXPECT_GE(triangles, 0.5) << query << ": " << r.out;
    EXPECT_LE(triangles, 1.0) << query << ": " << r.out;
  }
}

TEST(TraceRays, RejectsTruncatedFiles) {
  std::string dir = ::testing::TempDir();
  write<float>(dir + "bad_tris.bin", {0, 0, 1, 1, 0});  // not a multiple of 9 floats
  write<float>(dir + "rays1.bin", {0, 0, 0, 0, 0, 0, 1, 1});
  pt::test::ProcessResult r = run({dir + "bad_tris.bin", dir + "rays1.bin"});
  EXPECT_NE(r.err.find("bad_tris.bin"), std::string::npos) << r.err;
  EXPECT_EQ(r.exit_code, 1);
}

}  // namespace
