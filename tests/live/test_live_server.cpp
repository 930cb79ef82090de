// The live view's HTTP server in process, with short limits: the page and
// the API answer well-formed requests; hostile ones (bad numbers, NaN
// cameras, huge views, unknown routes, paths out of the start directory,
// missing guard headers, oversized or malformed requests, partial requests
// that stall, too many connections) each get a 4xx (or 503) and exactly one
// log line, and meanwhile the server goes on answering and the render goes on
// rendering.
#include <cstring>
#include <filesystem>
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

/// The server with the cornell scene, a session, limits short enough to test, and a captured log.
class LiveServer : public ::testing::Test {
 protected:
  static ServerLimits limits() {
    ServerLimits l;
    l.stream.request_time = milliseconds(400);
    l.stream.response_time = milliseconds(2000);
    l.keep_alive = milliseconds(1000);
    l.max_connections = 6;
    l.threads = 12;
    return l;
  }
  /// The session's log lines go to the server's log; a test sets fail_next_chunk to make the render throw.
  SessionConfig config(const Scene& s) {
    SessionConfig c;
    c.log = [this](const std::string& line) {
      std::lock_guard lock(log_mutex);
      log.push_back(line);
    };
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
    RouteConfig routes{dir.path(),
                       dir / "camera.txt",
                       dir / "image.png",
                       {host, "localhost:" + std::to_string(port)},
                       "cornell_spheres.dae",
                       milliseconds(3000)};
    add_routes(server, session, bvh, routes);
    listener = std::thread([this] { server.listen_after_bind(); });
    while (!server.is_running()) std::this_thread::sleep_for(milliseconds(1));
  }
  void TearDown() override {
    session.stop();
    server.stop();
    if (listener.joinable()) listener.join();
  }

  std::vector<std::string> log_lines() {
    std::lock_guard lock(log_mutex);
    return log;
  }
  /// Sends raw bytes; expects `status` and one new log line naming it.
  void expect_refused(const std::string& request, int status, const std::string& why = "") {
    size_t before = log_lines().size();
    std::string reply = test::exchange(port, request, milliseconds(3000));
    EXPECT_EQ(test::status_of(reply), status) << request.substr(0, 200) << "\n-> " << reply.substr(0, 300);
    for (int i = 0; i < 100 && log_lines().size() == before; ++i) std::this_thread::sleep_for(milliseconds(5));
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

  std::atomic<bool> fail_next_chunk{false};
  std::mutex log_mutex;
  std::vector<std::string> log;
  LoadResult loaded = load_collada_file(test::project_scene("cornell_spheres.dae"));
  SceneBvh4 bvh{loaded.scene};
  RenderSession session{loaded.scene, bvh, config(loaded.scene)};
  HttpServer server{limits(), [this](const std::string& line) {
                      std::lock_guard lock(log_mutex);
                      log.push_back(line);
                    }};
  test::ScratchDir dir;
  int port = 0;
  std::string host;
  std::thread listener;
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
  // The guard: a POST without the page's header, another site's Host, no Host.
  const std::string close = "Connection: close\r\n\r\n";
  expect_refused("POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host + "\r\nContent-Length: 0\r\n" + close, 403,
                 "X-PT-Live");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: evil.example:80\r\n" + close, 403, "evil.example");
  expect_refused("GET /api/state HTTP/1.1\r\n" + close, 403, "Host");
  // Malformed and oversized requests.
  expect_refused("GARBAGE\r\n\r\n", 400);
  expect_refused("GET /" + std::string(9000, 'a') + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n", 414);
  expect_refused("GET / HTTP/1.1\r\nHost: " + host + "\r\nX-Long: " + std::string(10000, 'b') + "\r\n\r\n", 400);
  expect_refused("POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host +
                     "\r\nX-PT-Live: 1\r\nContent-Type: text/plain\r\nContent-Length: 20000\r\n\r\n" +
                     std::string(20000, 'c'),
                 413);
  std::string many_headers = "GET / HTTP/1.1\r\nHost: " + host + "\r\n";
  for (int i = 0; i < 2000; ++i) many_headers += "X-" + std::to_string(i) + ": " + std::string(40, 'd') + "\r\n";
  expect_refused(many_headers + "\r\n", 400);  // the read stops at 64 KiB: the headers never end
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
  // A body that happens to hold the word is a body; a header merely starting with it is another header.
  httplib::Client c("127.0.0.1", port);
  auto posted = c.Post("/api/nav?op=still", httplib::Headers{{"X-PT-Live", "1"}, {"Ranges-Seen", "0-1"}},
                       "\r\nRange: bytes=0-1\r\n\r\n", "text/plain");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 200);
  EXPECT_EQ(log_lines().size(), 3u);
}

TEST_F(LiveServer, RequestBodiesAreTakenOnlyAsContentLengthBytesWithinTheLimit) {
  const std::string close = "Connection: close\r\n\r\n";
  const std::string head = "POST /api/nav?op=still HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n";
  // Chunks of 4 KiB, 30 KiB in all: more than the 16 KiB a body may have, but each piece small.
  std::string chunked;
  for (int i = 0; i < 30; ++i) chunked += "400\r\n" + std::string(1024, 'x') + "\r\n";
  expect_refused(head + "Transfer-Encoding: chunked\r\n" + close + chunked + "0\r\n\r\n", 411,
                 "Transfer-Encoding is not accepted");
  // A compressed body would be inflated past the limit (a few KiB of gzip can hold megabytes).
  expect_refused(head + "Content-Encoding: gzip\r\nContent-Length: 10\r\n" + close + std::string(10, 'z'), 415,
                 "Content-Encoding is not accepted");
  expect_refused(head + close, 411, "needs a Content-Length");
  expect_refused(head + "Content-Length: 3\r\nContent-Length: 3\r\n" + close + "abc", 400, "more than once");
  expect_refused(head + "Content-Length: 16385\r\n" + close + std::string(16385, 'y'), 413,
                 "a body of 16385 bytes is more than the 16384");
  // A GET's body would be read as the next request.
  expect_refused("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nContent-Length: 5\r\n" + close + "hello", 400,
                 "a GET takes no body");
  // A refused POST's body is left unread, so its connection closes instead of reading the body as a request.
  test::Probe probe(port);
  ASSERT_TRUE(
      probe.send("POST /api/nav?op=still HTTP/1.1\r\nHost: evil.example\r\nX-PT-Live: 1\r\n"
                 "Content-Length: 37\r\n\r\nGET /api/state HTTP/1.1\r\nHost: x\r\n\r\n"));
  std::string reply = probe.read_all(milliseconds(3000));
  EXPECT_EQ(test::status_of(reply), 403);
  EXPECT_EQ(reply.find("HTTP/1.1", 10), std::string::npos) << reply;
  // Within the limit, as Content-Length bytes, a body is fine.
  httplib::Client c("127.0.0.1", port);
  auto posted =
      c.Post("/api/nav?op=still", httplib::Headers{{"X-PT-Live", "1"}}, std::string(16384, 'b'), "text/plain");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 200);
}

TEST_F(LiveServer, StopEndsEveryConnectionAtOnce) {
  // An idle keep-alive connection, a frame request waiting for a frame, and a request that never ends.
  test::Probe idle(port), waiting(port), stalled(port);
  ASSERT_TRUE(idle.send("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\n\r\n"));
  ViewSettings one = session.view().settings;
  one.samples = 1;  // a view complete at once: no frame comes while the request waits
  const uint64_t version = session.set_settings(one);
  uint64_t last = 0;
  for (std::shared_ptr<const Frame> f; (f = session.frame_after(last, milliseconds(10000)));) {
    last = f->info.id;
    if (f->info.complete && f->info.view_version == version) break;
  }
  ASSERT_TRUE(waiting.send("GET /api/frame?after=" + std::to_string(last) + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n"));
  ASSERT_TRUE(stalled.send("GET /api/sta"));
  std::this_thread::sleep_for(milliseconds(100));
  const auto start = std::chrono::steady_clock::now();
  server.stop();  // as serve_live_view stops: the server, then the render
  session.stop();
  listener.join();
  const auto took = std::chrono::steady_clock::now() - start;
  EXPECT_LT(took, milliseconds(700)) << "the keep-alive wait is 1 s, the frame wait 3 s";
  std::string reply = waiting.read_all(milliseconds(1000));
  EXPECT_EQ(test::status_of(reply), 503) << reply.substr(0, 300);
  EXPECT_NE(reply.find("the server is stopping"), std::string::npos);
  EXPECT_TRUE(log_lines().empty()) << "the requests the stop ends are not refusals: " << log_lines().front();
}

TEST_F(LiveServer, AFailedRenderIsOneLogLineAndItsFrameRequestsAreAnswered500WithTheReason) {
  uint64_t newest = 0;  // the view complete: no frame comes but those of the next view
  for (std::shared_ptr<const Frame> f; (f = session.frame_after(newest, milliseconds(10000)));) {
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
  for (int i = 0; i < 100 && log_lines().size() < 2; ++i) std::this_thread::sleep_for(milliseconds(5));
  std::vector<std::string> lines = log_lines();  // the log line of a response follows its last byte
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
  const auto start = std::chrono::steady_clock::now();
  std::thread trickler([&] {  // one byte every 50 ms: never a whole request within 400 ms
    for (char ch : std::string("GET /api/state HTTP/1.1\r\n"))
      if (!trickle.send(std::string(1, ch))) break;
      else std::this_thread::sleep_for(milliseconds(50));
  });
  httplib::Client c("127.0.0.1", port);
  auto served = c.Get("/api/state");  // meanwhile
  ASSERT_TRUE(served);
  EXPECT_EQ(served->status, 200);
  EXPECT_EQ(test::status_of(partial_line.read_all(milliseconds(3000))), 408);
  EXPECT_EQ(test::status_of(partial_headers.read_all(milliseconds(3000))), 400);  // httplib: headers that never end
  EXPECT_EQ(test::status_of(trickle.read_all(milliseconds(3000))), 408);
  trickler.join();
  EXPECT_LT(std::chrono::steady_clock::now() - start, milliseconds(2500));
  int timeouts = 0;
  for (const std::string& line : log_lines()) timeouts += line.rfind("live: 408", 0) == 0;
  EXPECT_EQ(timeouts, 2);
}

TEST_F(LiveServer, ConnectionsBeyondTheLimitAreRefusedAndServiceResumes) {
  std::vector<std::unique_ptr<test::Probe>> idle;
  for (int i = 0; i < 6; ++i) idle.push_back(std::make_unique<test::Probe>(port));
  for (int i = 0; i < 200 && server.open_connections() < 6; ++i) std::this_thread::sleep_for(milliseconds(5));
  ASSERT_EQ(server.open_connections(), 6u);
  EXPECT_EQ(test::status_of(test::exchange(port, get("/api/state"), milliseconds(3000))), 503);
  idle.clear();
  for (int i = 0; i < 200 && server.open_connections() > 0; ++i) std::this_thread::sleep_for(milliseconds(5));
  EXPECT_EQ(test::status_of(test::exchange(port, get("/api/state"))), 200);
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
  for (int i = 0; i < 500; ++i) {
    nlohmann::json job = nlohmann::json::parse(c.Get("/api/render")->body);
    if (job["state"] != "rendering") {
      EXPECT_EQ(job["state"], "done") << job.dump();
      break;
    }
    std::this_thread::sleep_for(milliseconds(10));
  }
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
  for (int i = 0; i < 1000 && session.job().state == JobState::kRendering; ++i)
    std::this_thread::sleep_for(milliseconds(10));
  EXPECT_EQ(session.job().state, JobState::kFailed);
  EXPECT_NE(session.job().message.find("late.png exists"), std::string::npos) << session.job().message;
  EXPECT_EQ(std::filesystem::file_size(dir / "late.png"), 4u);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"late.png"})) << "no temporary file is left";
}

}  // namespace
}  // namespace pt::live
