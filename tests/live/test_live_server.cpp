// The live view's HTTP server in process, with small limits and a clock that
// moves only when a test moves it (no deadline passes by itself, so every
// test decides on events): the page and the API answer well-formed requests;
// hostile ones (bad numbers, NaN cameras, huge views, unknown routes, paths
// out of the start directory, missing or percent-encoded guard headers,
// bodies, oversized or malformed requests, partial requests that stall, too
// many connections from one client) each get a 4xx (or 503) and exactly one
// log line, and meanwhile the server goes on answering, every client keeps
// its share of the connections, and the render goes on rendering. Names that
// are not UTF-8 survive the JSON.
#include <algorithm>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <future>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "bvh/scene_bvh4.h"
#include "live/routes.h"
#include "support/http_probe.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt::live {
namespace {

using std::chrono::milliseconds;
constexpr int kW = 48, kH = 36;

/// The server's clock: it moves only when a test moves it.
struct ManualClock {
  const Clock::time_point start = Clock::now();
  std::atomic<int64_t> elapsed_ns{0};
  Clock::time_point now() const { return start + std::chrono::nanoseconds(elapsed_ns.load()); }
  void advance(Clock::duration d) { elapsed_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(d).count(); }
};

struct FixtureOptions {
  ServerLimits limits;
  std::string folder;  ///< the start directory: a folder of this name in the scratch directory ("": itself)
  std::string scene_name = "cornell_spheres.dae";
};

/// Limits small enough to reach: 8 connections, 6 per client, 2 frame requests waiting per client.
ServerLimits small_limits() {
  ServerLimits l;
  l.stream.request_time = milliseconds(400);
  l.stream.response_time = milliseconds(2000);
  l.keep_alive = milliseconds(1000);
  l.shares = {8, 6, 2};
  l.threads = 16;
  return l;
}

/// The server with the cornell scene, a session, the manual clock, and a captured log.
class LiveServerBase : public ::testing::Test {
 protected:
  explicit LiveServerBase(FixtureOptions options) : options_(std::move(options)) {}

  /// The session's log lines go to the server's log; a test sets fail_next_chunk to make the render throw.
  SessionConfig config(const Scene& s) {
    SessionConfig c;
    c.log = [this](const std::string& line) { add_log(line); };
    c.on_chunk = [this](uint64_t) {
      if (fail_next_chunk.exchange(false)) throw std::bad_alloc();
    };
    c.base.width = kW;
    c.base.height = kH;
    c.base.threads = 2;
    c.base.samples_per_pixel = 64;
    c.settings = view_settings_of(c.base);
    c.limits = nav_limits(s.bounds);
    c.camera = view_from_camera(resolve_camera(s, kW, kH), kW, kH, s.bounds.center(), c.limits);
    return c;
  }

  void SetUp() override {
    port = server.bind("127.0.0.1", 0);
    ASSERT_GT(port, 0);
    host = "127.0.0.1:" + std::to_string(port);
    start_dir = options_.folder.empty() ? dir.path() : dir / options_.folder;
    std::filesystem::create_directories(start_dir);
    // Frame requests wait up to a minute: only a frame, a failure or the stop ends one in a test.
    RouteConfig routes{start_dir,
                       start_dir / "camera.txt",
                       start_dir / "image.png",
                       {host, "localhost:" + std::to_string(port)},
                       options_.scene_name,
                       milliseconds(60000)};
    add_routes(server, session, bvh, routes);
    listener = std::thread([this] { server.listen_after_bind(); });
    ASSERT_TRUE(test::wait_until([this] { return server.is_running(); }));
  }
  void TearDown() override {
    session.stop();
    server.stop();
    if (listener.joinable()) listener.join();
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
  /// Sends raw bytes; expects `status` with one Connection header, "close" (the connection ends), and one new
  /// log line naming the status and `why`. The server writes the line before it closes the connection.
  void expect_refused(const std::string& request, int status, const std::string& why = "") {
    size_t before = log_lines().size();
    std::string reply = test::exchange(port, request, milliseconds(30000));
    EXPECT_EQ(test::status_of(reply), status) << request.substr(0, 200) << "\n-> " << reply.substr(0, 300);
    EXPECT_EQ(test::header_values(reply, "Connection"), std::vector<std::string>{"close"}) << reply.substr(0, 300);
    EXPECT_TRUE(test::header_values(reply, "Keep-Alive").empty()) << reply.substr(0, 300);
    std::vector<std::string> lines = log_lines();
    ASSERT_EQ(lines.size(), before + 1) << request.substr(0, 200);
    EXPECT_EQ(lines.back().rfind("live: " + std::to_string(status), 0), 0u) << lines.back();
    EXPECT_NE(lines.back().find(why), std::string::npos) << lines.back();
    EXPECT_EQ(lines.back().find('\n'), std::string::npos);
  }
  std::string get(const std::string& target) {
    return "GET " + target + " HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n";
  }
  std::string post(const std::string& target) {
    return "POST " + target + " HTTP/1.1\r\nHost: " + host +
           "\r\nX-PT-Live: 1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
  }
  httplib::Result client_post(httplib::Client& c, const std::string& target) {
    return c.Post(target.c_str(), httplib::Headers{{"X-PT-Live", "1"}}, "", "text/plain");
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
  LoadResult loaded = load_collada_file(test::project_scene("cornell_spheres.dae"));
  SceneBvh4 bvh{loaded.scene};
  RenderSession session{loaded.scene, bvh, config(loaded.scene)};
  HttpServer server{options_.limits, [this](const std::string& line) { add_log(line); },
                    [this] { return clock.now(); }};
  test::ScratchDir dir;
  std::filesystem::path start_dir;
  int port = 0;
  std::string host;
  std::thread listener;
};

class LiveServer : public LiveServerBase {
 protected:
  LiveServer() : LiveServerBase({small_limits(), "", "cornell_spheres.dae"}) {}
};

TEST_F(LiveServer, ServesTheEmbeddedPageWithItsGuardHeaders) {
  httplib::Client c("127.0.0.1", port);
  auto page = c.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_EQ(page->get_header_value("Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(page->body.find("<canvas id=\"image\""), std::string::npos);
  EXPECT_NE(page->get_header_value("Content-Security-Policy").find("default-src 'none'"), std::string::npos);
  EXPECT_EQ(page->get_header_value("X-Content-Type-Options"), "nosniff");
  for (const char* asset : {"/app.js", "/style.css"}) {
    auto r = c.Get(asset);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << asset;
    EXPECT_GT(r->body.size(), 1000u) << asset;
  }
  EXPECT_TRUE(log_lines().empty());
}

TEST_F(LiveServer, StateFramesAndMovesWork) {
  httplib::Client c("127.0.0.1", port);
  auto state = c.Get("/api/state");
  ASSERT_TRUE(state);
  ASSERT_EQ(state->status, 200);
  nlohmann::json s = nlohmann::json::parse(state->body);
  EXPECT_EQ(s["settings"]["width"], kW);
  EXPECT_EQ(s["isa"], std::string(isa_name(bvh.isa())));
  auto frame = c.Get("/api/frame?after=0");
  ASSERT_TRUE(frame);
  ASSERT_EQ(frame->status, 200);
  const std::string& body = frame->body;
  ASSERT_GE(body.size(), 4u);
  uint32_t n = uint8_t(body[0]) | uint8_t(body[1]) << 8 | uint8_t(body[2]) << 16 | uint32_t(uint8_t(body[3])) << 24;
  nlohmann::json meta = nlohmann::json::parse(body.substr(4, n));
  EXPECT_EQ(body.size(), 4 + n + size_t(meta["width"].get<int>()) * meta["height"].get<int>() * 4);
  auto moved = client_post(c, "/api/nav?op=orbit&dx=12.5&dy=-3");
  ASSERT_TRUE(moved);
  EXPECT_EQ(moved->status, 200);
  uint64_t version = nlohmann::json::parse(moved->body)["version"];
  // The next frames show the moved view.
  uint64_t after = meta["id"];
  for (int i = 0; i < 50; ++i) {
    auto f = c.Get(("/api/frame?after=" + std::to_string(after)).c_str());
    ASSERT_TRUE(f);
    ASSERT_EQ(f->status, 200);
    uint32_t m = uint8_t(f->body[0]) | uint8_t(f->body[1]) << 8 | uint8_t(f->body[2]) << 16;
    nlohmann::json fm = nlohmann::json::parse(f->body.substr(4, m));
    after = fm["id"];
    if (fm["version"] == version) return;
  }
  ADD_FAILURE() << "no frame of the moved view";
}

TEST_F(LiveServer, HostileRequestsGetA4xxAndOneLogLine) {
  expect_refused(get("/nope"), 404, "no such route");
  expect_refused(get("/../../etc/passwd"), 404);
  expect_refused(get("/app.js?x=1"), 400, "no parameters");
  expect_refused(get("/api/state?evil=1"), 400, "unknown parameter");
  expect_refused(post("/api/nav?op=orbit&dx=nan&dy=0"), 400, "dx: must be a number");
  expect_refused(post("/api/nav?op=orbit&dx=1e999&dy=0"), 400, "dx: must be a number");
  expect_refused(post("/api/nav?op=orbit&dx=1&dx=2&dy=0"), 400, "more than once");
  expect_refused(post("/api/nav?op=fly"), 400, "op: must be one of orbit, pan, zoom, reset");
  expect_refused(post("/api/nav?op=zoom&steps=1e6"), 400, "steps");
  expect_refused(post("/api/camera?position=nan,0,0&target=0,0,0"), 400, "position");
  expect_refused(post("/api/camera?position=1,1,1&target=1,1,1"), 400, "apart");
  expect_refused(post("/api/camera?position=0,0,1e9&target=0,0,0"), 400, "apart");  // beyond max_r: not clamped
  expect_refused(post("/api/camera?position=0,5,0&target=0,0,0"), 400, "straight above or below");
  expect_refused(post("/api/camera?position=0,0,5&target=0,0,0&vfov=180"), 400, "vfov");
  expect_refused(post("/api/settings?width=100000"), 400, "width: must be an integer from 16 to 4096");
  expect_refused(post("/api/settings?width=4096&height=4096"), 400, "at most 4194304 pixels");
  expect_refused(post("/api/settings?samples=0"), 400, "samples");
  expect_refused(post("/api/settings?display=wireframe"), 400, "display");
  expect_refused(get("/api/frame?after=-1"), 400, "after");
  expect_refused(get("/api/bvh/level?depth=1000"), 400, "depth");
  expect_refused(get("/api/bvh/walk?x=1e9&y=0"), 400, "x");
  expect_refused(post("/api/camera/save?name=../evil.txt"), 400, "name");
  expect_refused(post("/api/camera/save?name=%2Fetc%2Fevil.txt"), 400, "name");
  expect_refused(post("/api/render?name=x.sh"), 400, "name");
  // A name a shell would read as an option.
  expect_refused(post("/api/camera/save?name=-rf.txt"), 400, "not starting with '.' or '-'");
  expect_refused(post("/api/render?name=--help.png"), 400, "not starting with '.' or '-'");
  // The guard: a POST without the page's header, another site's Host, no Host.
  const std::string close = "Connection: close\r\n\r\n";
  expect_refused("POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host + "\r\nContent-Length: 0\r\n" + close, 403,
                 "X-PT-Live");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: evil.example:80\r\n" + close, 403, "evil.example");
  expect_refused("GET /api/state HTTP/1.1\r\n" + close, 403, "Host");
  // httplib decodes header values: the guard's headers percent-encoded would pass it decoded.
  std::string encoded_host = host;
  encoded_host.replace(encoded_host.find(':'), 1, "%3a");
  encoded_host.replace(encoded_host.find('.'), 1, "%2e");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: " + encoded_host + "\r\n" + close, 400,
                 "may not be percent-encoded");
  expect_refused(
      "POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: %31\r\nContent-Length: 0\r\n" + close, 400,
      "may not be percent-encoded");
  // Malformed and oversized requests.
  expect_refused("GARBAGE\r\n\r\n", 400);
  expect_refused("GET /" + std::string(9000, 'a') + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n", 414);
  expect_refused("GET / HTTP/1.1\r\nHost: " + host + "\r\nX-Long: " + std::string(10000, 'b') + "\r\n\r\n", 431,
                 "larger than 8192 bytes a line");
  expect_refused("GET / HTTP/1.1\r\nHost: " + host + "\r\nCookie: " + std::string(60000, 'b') + "\r\n\r\n", 431,
                 "larger than 8192 bytes a line");
  std::string many_headers = "GET / HTTP/1.1\r\nHost: " + host + "\r\n";
  for (int i = 0; i < 2000; ++i) many_headers += "X-" + std::to_string(i) + ": " + std::string(40, 'd') + "\r\n";
  expect_refused(many_headers + "\r\n", 431, "65536 in all");  // the read stops at 64 KiB: the headers never end
  // Nothing was written outside the start directory, nor in it.
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_FALSE(std::filesystem::exists(dir.path().parent_path() / "evil.txt"));
  for (const std::string& line : log_lines()) std::printf("    %s\n", line.c_str());
}

TEST_F(LiveServer, RangeHeadersAreRefusedBeforeHttplibReadsThem) {
  // Each range of a multipart answer is a copy of the body: thousands of them would make a frame gigabytes.
  std::string ranges = "bytes=0-";
  while (ranges.size() < 7000) ranges += ",0-";
  const std::string close = "Connection: close\r\n\r\n";
  expect_refused("GET /api/frame?after=0 HTTP/1.1\r\nHost: " + host + "\r\nRange: " + ranges + "\r\n" + close, 416,
                 "Range header is not accepted");
  expect_refused("GET / HTTP/1.1\r\nHost: " + host + "\r\nrAnGe: bytes=0-1\r\n" + close, 416, "Range");
  expect_refused("GET /app.js HTTP/1.1\r\nRange: bytes=0-,0-\r\nHost: " + host + "\r\n" + close, 416, "Range");
  // A body that happens to hold the word is a body (refused as a body); a header merely starting with it is
  // another header.
  expect_refused("POST /api/nav?op=still HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nContent-Length: 23\r\n" +
                     close + "\r\nRange: bytes=0-1\r\n\r\n",
                 413, "takes none");
  httplib::Client c("127.0.0.1", port);
  auto posted = client_post(c, "/api/nav?op=still");
  auto headed = c.Get("/api/state", httplib::Headers{{"Ranges-Seen", "0-1"}});
  ASSERT_TRUE(posted);
  ASSERT_TRUE(headed);
  EXPECT_EQ(posted->status, 200);
  EXPECT_EQ(headed->status, 200);
  EXPECT_EQ(log_lines().size(), 4u);
}

TEST_F(LiveServer, RequestBodiesAreRefusedBeforeTheyAreRead) {
  const std::string close = "Connection: close\r\n\r\n";
  const std::string head = "POST /api/nav?op=still HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n";
  // Chunks of 4 KiB, 30 KiB in all.
  std::string chunked;
  for (int i = 0; i < 30; ++i) chunked += "400\r\n" + std::string(1024, 'x') + "\r\n";
  expect_refused(head + "Transfer-Encoding: chunked\r\n" + close + chunked + "0\r\n\r\n", 411,
                 "Transfer-Encoding is not accepted");
  // A compressed body would be inflated past any limit (a few KiB of gzip can hold megabytes).
  expect_refused(head + "Content-Encoding: gzip\r\nContent-Length: 10\r\n" + close + std::string(10, 'z'), 415,
                 "Content-Encoding is not accepted");
  expect_refused(head + close, 411, "needs a Content-Length of 0");
  expect_refused(head + "Content-Length: 3\r\nContent-Length: 3\r\n" + close + "abc", 400, "more than once");
  // No route reads a body: one of any size is refused, a form's too (httplib would merge it into the parameters).
  expect_refused(head + "Content-Length: 1\r\n" + close + "b", 413,
                 "a body of 1 bytes is not accepted: POST /api/nav takes none");
  expect_refused(head + "Content-Length: 16385\r\n" + close + std::string(16385, 'y'), 413, "16385 bytes");
  expect_refused(
      head + "Content-Type: application/x-www-form-urlencoded\r\nContent-Length: 9\r\n" + close + "op=orbit&", 413,
      "takes none");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nContent-Length: 5\r\n" + close + "hello", 413,
                 "GET /api/state takes none");
  // A multipart body is refused before httplib parses its part headers (with std::regex: deep recursion on a
  // long header), whatever its length.
  const std::string part =
      "--b\r\nContent-Disposition: form-data; name=\"" + std::string(8000, 'n') + "\"\r\n\r\nv\r\n--b--\r\n";
  expect_refused(head + "Content-Type: multipart/form-data; boundary=b\r\nContent-Length: " +
                     std::to_string(part.size()) + "\r\n" + close + part,
                 415, "a multipart body is not accepted");
  expect_refused(head + "Content-Type: Multipart/Mixed; boundary=b\r\nContent-Length: 0\r\n" + close, 415, "multipart");
  // A refused POST's body is left unread, so its connection closes instead of reading the body as a request.
  test::Probe probe(port);
  ASSERT_TRUE(
      probe.send("POST /api/nav?op=still HTTP/1.1\r\nHost: evil.example\r\nX-PT-Live: 1\r\n"
                 "Content-Length: 37\r\n\r\nGET /api/state HTTP/1.1\r\nHost: x\r\n\r\n"));
  std::string reply = probe.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(reply), 413);
  EXPECT_EQ(reply.find("HTTP/1.1", 10), std::string::npos) << reply;
  // Without a body (Content-Length 0, in any number of digits), a POST is fine.
  httplib::Client c("127.0.0.1", port);
  auto posted = client_post(c, "/api/nav?op=still");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 200);
  std::string zeros = test::exchange(port, head + "Content-Length: 000\r\n" + close, milliseconds(30000));
  EXPECT_EQ(test::status_of(zeros), 200) << zeros;
}

TEST_F(LiveServer, OnlyResponsesThatCloseTheirConnectionSayConnectionClose) {
  // A response on a kept-alive connection says Keep-Alive, and the connection serves the next request.
  test::Probe probe(port);
  const std::string state = "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\n\r\n";
  ASSERT_TRUE(probe.send(state));
  std::string first = probe.read_response(milliseconds(30000));
  EXPECT_EQ(test::status_of(first), 200);
  EXPECT_TRUE(test::header_values(first, "Connection").empty()) << first.substr(0, 400);
  EXPECT_EQ(test::header_values(first, "Keep-Alive").size(), 1u) << first.substr(0, 400);
  // A refusal on it says close, once, without Keep-Alive, and closes.
  ASSERT_TRUE(probe.send("POST /api/nav?op=fly HTTP/1.1\r\nHost: " + host +
                         "\r\nX-PT-Live: 1\r\nContent-Length: 0\r\nConnection: keep-alive\r\n\r\n"));
  std::string refused = probe.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(refused), 400);
  EXPECT_EQ(test::header_values(refused, "Connection"), std::vector<std::string>{"close"}) << refused;
  EXPECT_TRUE(test::header_values(refused, "Keep-Alive").empty()) << refused;
}

TEST_F(LiveServer, StopEndsEveryConnectionAtOnce) {
  // An idle keep-alive connection, a frame request waiting for a frame, and a request that never ends. On the
  // server's clock no deadline passes, so a stop that waited for the keep-alive or the request to time out
  // would not end; the frame wait (a minute) would end with 204, not 503.
  test::Probe idle(port), waiting(port), stalled(port);
  ASSERT_TRUE(idle.send("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\n\r\n"));
  ASSERT_EQ(test::status_of(idle.read_response(milliseconds(30000))), 200);
  const uint64_t last = complete_view();
  ASSERT_TRUE(waiting.send("GET /api/frame?after=" + std::to_string(last) + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n"));
  ASSERT_TRUE(stalled.send("GET /api/sta"));
  ASSERT_TRUE(
      test::wait_until([this] { return server.shares().frame_waits() == 1 && server.open_connections() == 3; }));
  auto stopping = std::async(std::launch::async, [this] {
    server.stop();  // as serve_live_view stops: the server, then the render
    session.stop();
    listener.join();
  });
  const bool stopped = stopping.wait_for(std::chrono::seconds(60)) == std::future_status::ready;
  if (!stopped) clock.advance(std::chrono::hours(1));  // let the deadlines pass, so that the test ends
  stopping.get();
  EXPECT_TRUE(stopped) << "the stop waited for a connection's deadline";
  std::string reply = waiting.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(reply), 503) << reply.substr(0, 300);
  EXPECT_NE(reply.find("the server is stopping"), std::string::npos);
  EXPECT_EQ(idle.read_all(milliseconds(30000)), "") << "closed without a reply";
  EXPECT_EQ(stalled.read_all(milliseconds(30000)), "");
  EXPECT_TRUE(log_lines().empty()) << "the requests the stop ends are not refusals: " << log_lines().front();
}

TEST_F(LiveServer, AFailedRenderIsOneLogLineAndItsFrameRequestsAreAnswered500WithTheReason) {
  uint64_t newest = 0;  // the view complete: no frame comes but those of the next view
  for (std::shared_ptr<const Frame> f; (f = session.frame_after(newest, milliseconds(60000)));) {
    newest = f->info.id;
    if (f->info.complete) break;
  }
  fail_next_chunk.store(true);
  httplib::Client c("127.0.0.1", port);
  ASSERT_EQ(client_post(c, "/api/nav?op=orbit&dx=3&dy=0")->status, 200);
  auto frame = c.Get(("/api/frame?after=" + std::to_string(newest)).c_str());
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->status, 500);
  EXPECT_NE(frame->body.find("the render of this view failed: std::bad_alloc"), std::string::npos) << frame->body;
  // The log line of a response follows its last byte.
  ASSERT_TRUE(test::wait_until([this] { return log_lines().size() >= 2; }));
  std::vector<std::string> lines = log_lines();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].rfind("live: the render of view ", 0), 0u) << lines[0];
  EXPECT_EQ(lines[1].rfind("live: 500 GET /api/frame", 0), 0u) << lines[1];
  EXPECT_NE(nlohmann::json::parse(c.Get("/api/state")->body)["render_error"].get<std::string>().find("bad_alloc"),
            std::string::npos);
  // The server goes on, and the next change renders.
  ASSERT_EQ(client_post(c, "/api/nav?op=orbit&dx=3&dy=0")->status, 200);
  auto next = c.Get(("/api/frame?after=" + std::to_string(newest)).c_str());
  ASSERT_TRUE(next);
  EXPECT_EQ(next->status, 200);
}

TEST_F(LiveServer, StalledRequestsTimeOutWithA408WhileOthersAreServed) {
  test::Probe partial_line(port), partial_headers(port), trickle(port);
  ASSERT_TRUE(partial_line.send("GET /api/sta"));
  ASSERT_TRUE(partial_headers.send("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-Wait: "));
  ASSERT_TRUE(trickle.send("G"));
  // Each request's deadline is set once its first byte is there.
  ASSERT_TRUE(test::wait_until([this] { return server.shares().in_phase(ClientShares::Phase::kReading) == 3; }));
  httplib::Client c("127.0.0.1", port);
  auto served = c.Get("/api/state");  // meanwhile
  ASSERT_TRUE(served);
  EXPECT_EQ(served->status, 200);
  EXPECT_EQ(log_count("live: 408"), 0u) << "no deadline has passed on the server's clock";
  // A request's deadline (400 ms) is for all of it: the trickle's bytes keep coming, 50 ms apart on the server's
  // clock, and its deadline passes after the eighth all the same.
  for (char ch : std::string("ET /api/state HTTP/1.1\r\n")) {
    if (!trickle.send(std::string(1, ch))) break;
    clock.advance(milliseconds(50));
  }
  clock.advance(milliseconds(1));
  EXPECT_EQ(test::status_of(partial_line.read_all(milliseconds(30000))), 408);
  EXPECT_EQ(test::status_of(partial_headers.read_all(milliseconds(30000))), 408);
  EXPECT_EQ(test::status_of(trickle.read_all(milliseconds(30000))), 408);
  EXPECT_EQ(log_count("live: 408"), 3u);
  EXPECT_EQ(log_count("no complete request within 400 ms"), 3u);
}

TEST_F(LiveServer, AClientBeyondItsShareIsRefusedAndAClientWithinItTakesAConnectionOfTheHeaviest) {
  // 127.0.0.1 takes its share, 6 of the 8 connections; a seventh is refused.
  std::vector<std::unique_ptr<test::Probe>> heavy;
  for (int i = 0; i < 6; ++i) heavy.push_back(std::make_unique<test::Probe>(port, "127.0.0.1"));
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 6; }));
  std::string refused = test::exchange(port, get("/api/state"), milliseconds(30000), "127.0.0.1");
  EXPECT_EQ(test::status_of(refused), 503);
  EXPECT_EQ(test::header_values(refused, "Connection"), std::vector<std::string>{"close"});
  EXPECT_EQ(log_count("127.0.0.1 has 6 connections open, as many as one client may; refused"), 1u);
  // 127.0.0.2 takes the last two: the server is full.
  test::Probe second_a(port, "127.0.0.2"), second_b(port, "127.0.0.2");
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 8; }));
  // 127.0.0.3 is served all the same: its connection takes one of 127.0.0.1's idle ones.
  EXPECT_EQ(test::status_of(test::exchange(port, get("/api/state"), milliseconds(30000), "127.0.0.3")), 200);
  EXPECT_EQ(log_count("live: a connection of 127.0.0.1 closed for one of 127.0.0.3"), 1u);
  EXPECT_EQ(server.shares().held_by("127.0.0.1"), 5u);
  // So is 127.0.0.2 with a third connection (it holds 2, 127.0.0.1 holds 5).
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 7; }));
  test::Probe second_c(port, "127.0.0.2");
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 8; }));
  EXPECT_EQ(test::status_of(test::exchange(port, get("/api/state"), milliseconds(30000), "127.0.0.2")), 200);
  EXPECT_EQ(log_count("live: a connection of 127.0.0.1 closed for one of 127.0.0.2"), 1u);
  EXPECT_EQ(server.shares().held_by("127.0.0.1"), 4u);
  // Once the connections close, service is as before.
  heavy.clear();
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 3; }));
  EXPECT_EQ(test::status_of(test::exchange(port, get("/api/state"), milliseconds(30000))), 200);
}

TEST_F(LiveServer, FrameRequestsBeyondAClientsShareGet429) {
  const uint64_t last = complete_view();
  const std::string wait = "GET /api/frame?after=" + std::to_string(last) + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n";
  test::Probe first(port), second(port), other(port, "127.0.0.2");
  ASSERT_TRUE(first.send(wait));
  ASSERT_TRUE(second.send(wait));
  ASSERT_TRUE(test::wait_until([this] { return server.shares().frame_waits() == 2; }));
  std::string refused = test::exchange(port, get("/api/frame?after=" + std::to_string(last)), milliseconds(30000));
  EXPECT_EQ(test::status_of(refused), 429) << refused.substr(0, 300);
  EXPECT_NE(refused.find("this client has 2 frame requests waiting already"), std::string::npos);
  // Another client has its own share; and the next frame answers every waiting request.
  ASSERT_TRUE(other.send(wait));
  ASSERT_TRUE(test::wait_until([this] { return server.shares().frame_waits() == 3; }));
  httplib::Client c("127.0.0.1", port);
  ASSERT_EQ(client_post(c, "/api/nav?op=orbit&dx=3&dy=0")->status, 200);
  for (test::Probe* p : {&first, &second, &other})
    EXPECT_EQ(test::status_of(p->read_response(milliseconds(30000))), 200);
  EXPECT_EQ(log_count("live: 429"), 1u);
}

/// The server at the product's limits (48 connections, 16 per client, 6 frame waits per client, 64 threads).
class LiveServerAtProductLimits : public LiveServerBase {
 protected:
  LiveServerAtProductLimits() : LiveServerBase({ServerLimits{}, "", "cornell_spheres.dae"}) {}

  /// The page, the state and a frame, each on a new connection from 127.0.0.1: their statuses.
  std::vector<int> visit() {
    std::vector<int> statuses;
    for (const char* target : {"/", "/api/state", "/api/frame?after=0"})
      statuses.push_back(test::status_of(test::exchange(port, get(target), milliseconds(30000), "127.0.0.1")));
    return statuses;
  }
};

/// Attacking connections, each on its own thread, from `addresses` in turn; each opens its connection again when
/// the server refuses or closes it. They stop when the object goes (each sends at most `rounds` times).
class Attack {
 public:
  /// `next` writes a connection's next bytes: its first request, or its next bytes on it.
  using Next = std::function<std::string(bool first)>;
  /// `answered`: a connection reads a whole response after each send (a client that sends requests), else
  /// nothing (a client that never finishes its request).
  Attack(int port, const std::vector<std::string>& addresses, int connections, Next next, bool answered,
         int rounds = 600) {
    for (int i = 0; i < connections; ++i)
      threads_.emplace_back([=, this] { run(port, addresses[size_t(i) % addresses.size()], next, answered, rounds); });
  }
  ~Attack() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  /// Connections whose first request was answered (with any status, or by closing the connection).
  int answered() const { return answered_.load(); }
  /// Connections whose first request was answered 200, and sends that were refused or cut (then reopened).
  int served() const { return served_.load(); }
  int refused() const { return refused_.load(); }

 private:
  void run(int port, const std::string& from, const Next& next, bool answered, int rounds) {
    std::unique_ptr<test::Probe> probe;
    bool first = true, counted = false, was_answered = false;
    for (int round = 0; round < rounds; ++round) {
      if (!probe) {
        probe = std::make_unique<test::Probe>(port, from);
        first = true;
      }
      bool ok = probe->send(next(first));
      if (ok && answered) {
        const int status = test::status_of(probe->read_response(milliseconds(30000)));
        ok = status == 200;
        if (!was_answered) answered_ += was_answered = true;
        if (ok && !counted) served_ += counted = true;
      }
      if (!ok) {
        ++refused_;
        probe.reset();
      }
      first = false;
      // A tenth of a second between sends: a pace, not a measurement.
      std::unique_lock lock(mutex_);
      if (cv_.wait_for(lock, milliseconds(100), [this] { return stop_; })) return;
    }
  }

  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::atomic<int> answered_{0}, served_{0}, refused_{0};
  std::vector<std::thread> threads_;
};

TEST_F(LiveServerAtProductLimits, FortyEightConnectionsFromOneClientLeaveAnotherItsPageStateAndFrames) {
  const std::string request = "GET /api/render HTTP/1.1\r\nHost: " + host + "\r\n\r\n";
  Attack attack(
      port, {"127.0.0.2"}, 48, [&](bool) { return request; }, true);
  // In place: every connection's first request answered; the client holds its share, 16 connections, and its
  // other 32 are refused (and come back).
  ASSERT_TRUE(test::wait_until([&] { return attack.answered() == 48; }));
  EXPECT_EQ(attack.served(), 16);
  EXPECT_EQ(server.shares().held_by("127.0.0.2"), 16u);
  EXPECT_EQ(visit(), (std::vector<int>{200, 200, 200}));
  EXPECT_EQ(server.shares().held_by("127.0.0.2"), 16u) << "the attack went on meanwhile";
  EXPECT_EQ(log_count("from 127.0.0.1:"), 0u) << "no request of the other client was refused";
}

TEST_F(LiveServerAtProductLimits, FortyEightConnectionsFromThreeClientsLeaveAnotherItsPageStateAndFrames) {
  const std::string request = "GET /api/render HTTP/1.1\r\nHost: " + host + "\r\n\r\n";
  Attack attack(
      port, {"127.0.0.2", "127.0.0.3", "127.0.0.4"}, 48, [&](bool) { return request; }, true);
  // In place: every connection of the server taken, 16 by each client.
  ASSERT_TRUE(test::wait_until([&] { return attack.served() == 48; }));
  EXPECT_EQ(server.open_connections(), 48u);
  // The other client's first connection takes one of theirs (the next may find the slot its last one left).
  EXPECT_EQ(visit(), (std::vector<int>{200, 200, 200}));
  EXPECT_GE(log_count("closed for one of 127.0.0.1"), 1u);
  EXPECT_EQ(log_count("from 127.0.0.1:"), 0u) << "no request of the other client was refused";
}

TEST_F(LiveServerAtProductLimits, FiftySlowlorisConnectionsLeaveAnotherItsPageStateAndFrames) {
  // Requests that never end, one byte at a time, from five clients; on the server's clock no deadline passes,
  // so none of them times out by itself.
  const std::string start = "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-Slow: ";
  Attack attack(
      port, {"127.0.0.2", "127.0.0.3", "127.0.0.4", "127.0.0.5", "127.0.0.6"}, 50,
      [&](bool first) { return first ? start : std::string("a"); }, false);
  ASSERT_TRUE(test::wait_until([&] { return server.open_connections() == 48 && attack.refused() >= 2; }));
  EXPECT_EQ(visit(), (std::vector<int>{200, 200, 200}));
  EXPECT_GE(log_count("closed for one of 127.0.0.1"), 1u);
  EXPECT_EQ(log_count("from 127.0.0.1:"), 0u) << "no request of the other client was refused";
  EXPECT_EQ(log_count("live: 408"), 0u);
}

/// The server started in a folder whose name is not UTF-8, on a scene whose name is Latin-1.
class LiveServerWithForeignNames : public LiveServerBase {
 protected:
  LiveServerWithForeignNames() : LiveServerBase({small_limits(), "\xff", "sc\xe9.dae"}) {}
};

TEST_F(LiveServerWithForeignNames, NamesThatAreNotUtf8SurviveTheJsonAndEachReplyNamesTheFileWritten) {
  // Each byte that is not UTF-8 reaches the JSON as U+FFFD (EF BF BD in UTF-8).
  const std::string folder = (dir.path() / "\xef\xbf\xbd").string();
  httplib::Client c("127.0.0.1", port);
  auto state = c.Get("/api/state");
  ASSERT_TRUE(state);
  ASSERT_EQ(state->status, 200) << state->body;
  EXPECT_EQ(nlohmann::json::parse(state->body)["scene"], "sc\xef\xbf\xbd.dae");
  auto saved = client_post(c, "/api/camera/save?name=u.txt");
  ASSERT_TRUE(saved);
  ASSERT_EQ(saved->status, 200) << saved->body;
  EXPECT_EQ(nlohmann::json::parse(saved->body)["file"], folder + "/u.txt");
  ASSERT_EQ(client_post(c, "/api/settings?samples=2")->status, 200);
  auto render = client_post(c, "/api/render?name=u.png");
  ASSERT_TRUE(render);
  ASSERT_EQ(render->status, 202) << render->body;
  EXPECT_EQ(nlohmann::json::parse(render->body)["file"], folder + "/u.png");
  nlohmann::json job;
  ASSERT_TRUE(test::wait_until([&] {
    auto r = c.Get("/api/render");
    EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "no reply");
    job = r && r->status == 200 ? nlohmann::json::parse(r->body) : nlohmann::json{{"state", "failed"}};
    return job["state"] != "rendering";
  }));
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_EQ(job["file"], folder + "/u.png");
  auto after = c.Get("/api/state");
  ASSERT_TRUE(after);
  EXPECT_EQ(after->status, 200) << after->body;
  std::vector<std::string> written;
  for (const auto& e : std::filesystem::directory_iterator(start_dir)) written.push_back(e.path().filename());
  std::sort(written.begin(), written.end());
  EXPECT_EQ(written, (std::vector<std::string>{"u.png", "u.txt"}));
  EXPECT_TRUE(log_lines().empty());
}

TEST_F(LiveServer, FilesAreWrittenOnlyIntoTheStartDirectoryUnderTheirNames) {
  httplib::Client c("127.0.0.1", port);
  auto saved = client_post(c, "/api/camera/save?name=my_view.txt");
  ASSERT_TRUE(saved);
  ASSERT_EQ(saved->status, 200) << saved->body;
  EXPECT_EQ(nlohmann::json::parse(saved->body)["file"], (dir / "my_view.txt").string());
  EXPECT_EQ(format_camera_settings(read_camera_settings_file(dir / "my_view.txt")),
            format_camera_settings(session.view().camera));
  ASSERT_EQ(client_post(c, "/api/camera/save")->status, 200);
  EXPECT_TRUE(std::filesystem::exists(dir / "camera.txt"));
  auto small = client_post(c, "/api/settings?samples=2");
  ASSERT_EQ(small->status, 200);
  auto render = client_post(c, "/api/render?name=shot.png");
  ASSERT_TRUE(render);
  ASSERT_EQ(render->status, 202) << render->body;
  nlohmann::json job;
  ASSERT_TRUE(test::wait_until([&] {
    job = nlohmann::json::parse(c.Get("/api/render")->body);
    return job["state"] != "rendering";
  }));
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_TRUE(std::filesystem::exists(dir / "shot.png"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"camera.txt", "my_view.txt", "shot.png"}));
}

TEST_F(LiveServer, ASavedCameraHasTheScreenFieldsOfTheViewsSizeNow) {
  httplib::Client c("127.0.0.1", port);
  ASSERT_EQ(client_post(c, "/api/settings?width=96&height=36")->status, 200);
  ASSERT_EQ(client_post(c, "/api/camera/save?name=wide.txt")->status, 200);
  const CameraSettingsFile f = read_camera_settings_file(dir / "wide.txt");
  EXPECT_FLOAT_EQ(f.aspect, 96.0f / 36.0f);
  EXPECT_EQ(f.screen_w, 96.0f);
  EXPECT_EQ(f.screen_h, 36.0f);
  const Camera saved = resolve_camera(f, 96, 36), view = resolve_camera(session.view().camera, 96, 36);
  EXPECT_EQ(std::memcmp(&saved, &view, sizeof(Camera)), 0) << "-c FILE renders the view";
  EXPECT_FLOAT_EQ(f.screen_dist, float(36 / (2.0 * view.tan_half_vfov)));
}

TEST_F(LiveServer, ANamedFileNeverReplacesAnExistingOne) {
  auto write = [this](const char* name) {
    std::FILE* f = std::fopen((dir / name).c_str(), "w");
    std::fputs("mine", f);
    std::fclose(f);
  };
  auto read = [this](const char* name) {
    std::string text(16, '\0');
    std::FILE* f = std::fopen((dir / name).c_str(), "r");
    text.resize(std::fread(text.data(), 1, text.size(), f));
    std::fclose(f);
    return text;
  };
  write("taken.txt");
  write("taken.png");
  write("shot_rate.png");
  expect_refused(post("/api/camera/save?name=taken.txt"), 409, "taken.txt exists");
  expect_refused(post("/api/render?name=taken.png"), 409, "taken.png exists");
  // Under adaptive sampling the Render button also writes NAME_rate.png.
  httplib::Client c("127.0.0.1", port);
  ASSERT_EQ(client_post(c, "/api/settings?samples=2&adaptive_tolerance=0.5&adaptive_batch=1")->status, 200);
  expect_refused(post("/api/render?name=shot.png"), 409, "shot_rate.png exists");
  EXPECT_EQ(read("taken.txt"), "mine");
  EXPECT_EQ(read("taken.png"), "mine");
  EXPECT_EQ(read("shot_rate.png"), "mine");
  // A new name is written, once: the second save of it is refused.
  ASSERT_EQ(client_post(c, "/api/camera/save?name=new.txt")->status, 200);
  expect_refused(post("/api/camera/save?name=new.txt"), 409, "new.txt exists");
  // The default files are the command line's: saved again, they are replaced.
  ASSERT_EQ(client_post(c, "/api/camera/save")->status, 200);
  ASSERT_EQ(client_post(c, "/api/camera/save")->status, 200);
  EXPECT_EQ(dir.entries(),
            (std::vector<std::string>{"camera.txt", "new.txt", "shot_rate.png", "taken.png", "taken.txt"}));
}

TEST_F(LiveServer, ARenderJobWhoseNameAppearsMeanwhileFailsAndReplacesNothing) {
  httplib::Client c("127.0.0.1", port);
  ASSERT_EQ(client_post(c, "/api/settings?samples=64")->status, 200);
  // The name is free when the job starts and taken before the view has its samples.
  ASSERT_EQ(session.start_job(dir / "late.png", false), "");
  std::FILE* f = std::fopen((dir / "late.png").c_str(), "w");
  std::fputs("mine", f);
  std::fclose(f);
  ASSERT_TRUE(test::wait_until([this] { return session.job().state != JobState::kRendering; }));
  EXPECT_EQ(session.job().state, JobState::kFailed);
  EXPECT_NE(session.job().message.find("late.png exists"), std::string::npos) << session.job().message;
  EXPECT_EQ(std::filesystem::file_size(dir / "late.png"), 4u);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"late.png"})) << "no temporary file is left";
}

}  // namespace
}  // namespace pt::live
