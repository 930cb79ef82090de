// The live view's server in process for the tests: the cornell scene, a
// render session, the routes, a captured log, and a clock that moves only
// when a test moves it (no deadline passes by itself, so every test decides
// on events); and a client that writes raw requests and reads raw replies.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bvh/scene_bvh4.h"
#include "live/routes.h"
#include "support/http_probe.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt::live::test_server {

using std::chrono::milliseconds;

/// The server's clock: it moves only when a test moves it.
struct ManualClock {
  const Clock::time_point start = Clock::now();
  std::atomic<int64_t> elapsed_ns{0};
  Clock::time_point now() const { return start + std::chrono::nanoseconds(elapsed_ns.load()); }
  void advance(Clock::duration d) { elapsed_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(d).count(); }
};

struct FixtureOptions {
  ServerLimits limits;
  int width = 48, height = 36;
  int samples = 64;
  Display display = Display::kImage;
  std::string scene_name = "cornell_spheres.dae";
};

/// Limits small enough to reach: 8 connections, 6 per client, 2 frame requests waiting per client.
inline ServerLimits small_limits() {
  ServerLimits l;
  l.keep_alive = milliseconds(1000);
  l.request_time = milliseconds(400);
  l.response_time = milliseconds(2000);
  l.shares = {8, 6, 2};
  l.threads = 2;
  l.max_sockets = 16;
  return l;
}

/// A reply as it came: status (-1: none), head and body.
struct Reply {
  std::string raw;
  int status() const { return test::status_of(raw); }
  std::string body() const { return test::body_of(raw); }
  nlohmann::json json() const { return nlohmann::json::parse(body(), nullptr, false); }
  std::vector<std::string> header(const std::string& name) const { return test::header_values(raw, name); }
};

/// A frame reply's JSON (the pixels follow it: `pixels` bytes of them).
inline nlohmann::json frame_meta(const std::string& body, size_t* pixels = nullptr) {
  if (body.size() < 4) return nlohmann::json();
  const uint32_t n =
      uint8_t(body[0]) | uint8_t(body[1]) << 8 | uint8_t(body[2]) << 16 | uint32_t(uint8_t(body[3])) << 24;
  if (pixels) *pixels = body.size() - 4 - std::min<size_t>(n, body.size() - 4);
  return nlohmann::json::parse(body.substr(4, n), nullptr, false);
}

class LiveServerBase : public ::testing::Test {
 protected:
  explicit LiveServerBase(FixtureOptions options) : options_(std::move(options)) {}

  /// The session's log lines go to the server's log; a test sets fail_next_chunk to make the render throw.
  SessionConfig config(const Scene& s) {
    SessionConfig c;
    c.log = [this](const std::string& line) { add_log(line); };
    c.frames_changed = [this] { server.wake(); };
    c.on_chunk = [this](uint64_t) {
      if (fail_next_chunk.exchange(false)) throw std::bad_alloc();
    };
    c.base.width = options_.width;
    c.base.height = options_.height;
    c.base.threads = 2;
    c.base.samples_per_pixel = options_.samples;
    c.settings = view_settings_of(c.base);
    c.settings.display = options_.display;
    c.limits = nav_limits(s.bounds);
    c.camera = view_from_camera(resolve_camera(s, options_.width, options_.height), options_.width, options_.height,
                                s.bounds.center(), c.limits);
    return c;
  }

  void SetUp() override {
    port = server.bind("127.0.0.1", 0);
    ASSERT_GT(port, 0);
    host = "127.0.0.1:" + std::to_string(port);
    // Frame requests wait up to a minute: only a frame, a failure or the stop ends one in a test.
    RouteConfig routes{dir.path(),          dir / "camera.txt",
                       dir / "image.png",   {host, "localhost:" + std::to_string(port)},
                       options_.scene_name, milliseconds(60000)};
    add_routes(server, session, bvh, routes);
    ASSERT_TRUE(server.start());
  }
  void TearDown() override {
    session.stop();
    server.stop();
  }

  void add_log(const std::string& line) {
    std::lock_guard lock(log_mutex);
    log.push_back(line);
  }
  std::vector<std::string> log_lines() {
    std::lock_guard lock(log_mutex);
    return log;
  }
  size_t log_count(const std::string& part) {
    size_t n = 0;
    for (const std::string& line : log_lines()) n += line.find(part) != std::string::npos;
    return n;
  }
  /// A request as the page makes it (with X-PT-Live), on a connection of its own.
  std::string get(const std::string& target) {
    return "GET " + target + " HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nConnection: close\r\n\r\n";
  }
  std::string post(const std::string& target) {
    return "POST " + target + " HTTP/1.1\r\nHost: " + host +
           "\r\nX-PT-Live: 1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
  }
  Reply send(const std::string& request, const std::string& from = "127.0.0.1") {
    return {test::exchange(port, request, milliseconds(30000), from)};
  }
  Reply GET(const std::string& target) { return send(get(target)); }
  Reply POST(const std::string& target) { return send(post(target)); }
  /// Sends raw bytes; expects `status` with one Connection header, "close" (the connection ends), and one new
  /// log line naming the status and `why`. The server writes the line before it answers.
  void expect_refused(const std::string& request, int status, const std::string& why = "") {
    size_t before = log_lines().size();
    Reply reply = send(request);
    EXPECT_EQ(reply.status(), status) << request.substr(0, 200) << "\n-> " << reply.raw.substr(0, 300);
    EXPECT_EQ(reply.header("Connection"), std::vector<std::string>{"close"}) << reply.raw.substr(0, 300);
    EXPECT_TRUE(reply.header("Keep-Alive").empty()) << reply.raw.substr(0, 300);
    std::vector<std::string> lines = log_lines();
    ASSERT_EQ(lines.size(), before + 1) << request.substr(0, 200);
    EXPECT_EQ(lines.back().rfind("live: " + std::to_string(status), 0), 0u) << lines.back();
    EXPECT_NE(lines.back().find(why), std::string::npos) << lines.back();
    EXPECT_EQ(lines.back().find('\n'), std::string::npos);
  }
  /// Makes the view complete at one sample, so that no frame comes until the next change; its last frame's id.
  uint64_t complete_view() {
    ViewSettings one = session.view().settings;
    one.samples = 1;
    const uint64_t version = session.set_settings(one);
    uint64_t last = 0;
    for (std::shared_ptr<const Frame> f; (f = session.frame_after(last, milliseconds(60000)));) {
      last = f->info.id;
      if (f->info.complete && f->info.view_version == version) break;
    }
    return last;
  }

  FixtureOptions options_;
  ManualClock clock;
  std::atomic<bool> fail_next_chunk{false};
  std::mutex log_mutex;
  std::vector<std::string> log;
  test::ScratchDir dir;
  LoadResult loaded = load_collada_file(test::project_scene("cornell_spheres.dae"));
  SceneBvh4 bvh{loaded.scene};
  // The server before the session: the session's frames wake it from the start.
  HttpServer server{options_.limits, [this](const std::string& line) { add_log(line); },
                    [this] { return clock.now(); }};
  RenderSession session{loaded.scene, bvh, config(loaded.scene)};
  int port = 0;
  std::string host;
};

}  // namespace pt::live::test_server
