// Hostile requests to `pathtracer --serve`, through the binary as a user
// runs it, by a scripted client that writes raw bytes: each bad request (bad
// numbers, a NaN camera, a huge view, unknown routes and methods, paths out
// of the start directory, requests without the page's guard, malformed,
// oversized and stalled requests) gets a 4xx and exactly one log line on
// stderr; the server keeps answering and the render keeps rendering
// meanwhile; Ctrl-C ends it with exit code 0. Also the --serve flags that
// must be refused before anything starts, and a server on every address
// that still answers only to this machine's names.
#include <signal.h>
#include <unistd.h>

#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/http_probe.h"
#include "support/run_process.h"

namespace pt {
namespace {

using std::chrono::milliseconds;

struct LiveServerProcess {
  test::ScratchDir dir;
  test::BackgroundProcess process{
      PT_PATHTRACER_BINARY, {"--serve", "0", "-r", "32", "24", "-s", "4", PT_DEFAULT_SCENE}, dir.path()};
  int port = 0;
  std::string host;

  LiveServerProcess() {
    std::string line = process.wait_for_line("http://127.0.0.1:", milliseconds(30000));
    size_t at = line.find("127.0.0.1:");
    if (at != std::string::npos) port = std::atoi(line.c_str() + at + 10);
    host = "127.0.0.1:" + std::to_string(port);
  }
  size_t log_lines() { return test::lines_of(process.err()).size(); }
  std::string request(const std::string& method, const std::string& target, const std::string& headers = "") {
    return method + " " + target + " HTTP/1.1\r\nHost: " + host + "\r\n" + headers +
           (method == "POST" ? "X-PT-Live: 1\r\nContent-Length: 0\r\n" : "") + "Connection: close\r\n\r\n";
  }
};

struct HostileRequest {
  const char* name;
  std::function<std::string(LiveServerProcess&)> bytes;
  int status;
  const char* log;  ///< part of the log line
};

std::vector<HostileRequest> hostile_requests() {
  auto get = [](const char* target) { return [target](LiveServerProcess& s) { return s.request("GET", target); }; };
  auto post = [](const char* target) { return [target](LiveServerProcess& s) { return s.request("POST", target); }; };
  return {
      {"unknown_route", get("/admin"), 404, "no such route"},
      {"file_path", get("/../../../../etc/passwd"), 404, "no such route"},
      {"encoded_file_path", get("/%2e%2e/%2e%2e/etc/passwd"), 404, "no such route"},
      {"unknown_method", [](LiveServerProcess& s) { return s.request("DELETE", "/api/state"); }, 405,
       "method DELETE is not used here"},
      {"nan_orbit", post("/api/nav?op=orbit&dx=NaN&dy=1"), 400, "dx: must be a number"},
      {"infinite_pan", post("/api/nav?op=pan&dx=1&dy=-inf"), 400, "dy: must be a number"},
      {"hex_zoom", post("/api/nav?op=zoom&steps=0x10"), 400, "steps: must be a number"},
      {"nan_camera", post("/api/camera?position=0,nan,5&target=0,0,0"), 400, "position: must be three finite numbers"},
      {"camera_beyond_the_coordinate_limit", post("/api/camera?position=1e30,0,0&target=0,0,0"), 400, "position"},
      {"huge_view", post("/api/settings?width=4096&height=4096"), 400, "at most 4194304 pixels"},
      {"huge_width", post("/api/settings?width=1000000000000"), 400, "width: must be an integer from 16 to 4096"},
      {"negative_samples", post("/api/settings?samples=-1"), 400, "samples: must be an integer"},
      {"unknown_setting", post("/api/settings?evil=1"), 400, "unknown parameter \"evil\""},
      {"camera_file_out_of_the_directory", post("/api/camera/save?name=..%2F..%2Fcam.txt"), 400, "name: must be"},
      {"image_with_a_directory", post("/api/render?name=sub%2Fx.png"), 400, "name: must be"},
      {"post_without_the_page_header",
       [](LiveServerProcess& s) {
         return "POST /api/nav?op=reset HTTP/1.1\r\nHost: " + s.host +
                "\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
       },
       403, "X-PT-Live"},
      {"dns_rebinding_host",
       [](LiveServerProcess&) {
         return std::string("GET /api/state HTTP/1.1\r\nHost: attacker.example\r\nConnection: close\r\n\r\n");
       },
       403, "attacker.example"},
      {"garbage",
       [](LiveServerProcess&) { return std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03\r\n\r\n", 15); }, 400,
       "malformed request"},
      {"request_line_of_20_kb",
       [](LiveServerProcess& s) {
         return "GET /" + std::string(20000, 'a') + " HTTP/1.1\r\nHost: " + s.host + "\r\n\r\n";
       },
       414, "request line too long"},
      {"header_of_20_kb",
       [](LiveServerProcess& s) {
         return "GET / HTTP/1.1\r\nHost: " + s.host + "\r\nCookie: " + std::string(20000, 'c') + "\r\n\r\n";
       },
       400, "malformed request"},
      {"body_of_1_mb",
       [](LiveServerProcess& s) {
         return "POST /api/settings?samples=2 HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: 1\r\nContent-Type: text/plain\r\nContent-Length: 1000000\r\n\r\n" +
                std::string(100000, 'x');
       },
       413, "a body of 1000000 bytes is more than the 16384 taken"},
      {"range_of_two_thousand_parts",
       [](LiveServerProcess& s) {
         std::string ranges = "bytes=0-";
         while (ranges.size() < 7000) ranges += ",0-";
         return s.request("GET", "/api/frame?after=0", "Range: " + ranges + "\r\n");
       },
       416, "a Range header is not accepted"},
      {"chunked_body_past_the_limit",
       [](LiveServerProcess& s) {
         std::string chunks;
         for (int i = 0; i < 30; ++i) chunks += "400\r\n" + std::string(1024, 'x') + "\r\n";
         return "POST /api/nav?op=still HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: 1\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n" + chunks + "0\r\n\r\n";
       },
       411, "Transfer-Encoding is not accepted"},
      {"compressed_body",
       [](LiveServerProcess& s) {
         return "POST /api/nav?op=still HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: 1\r\nContent-Encoding: br\r\nContent-Length: 4\r\nConnection: close\r\n\r\nzzzz";
       },
       415, "Content-Encoding is not accepted"},
      {"get_with_a_body",
       [](LiveServerProcess& s) { return s.request("GET", "/api/state", "Content-Length: 4\r\n") + "abcd"; }, 400,
       "a GET takes no body"},
  };
}

TEST(HostileRequests, EachGetsA4xxAndOneLogLineAndTheRenderGoesOn) {
  LiveServerProcess server;
  ASSERT_GT(server.port, 0) << server.process.err();
  for (const HostileRequest& r : hostile_requests()) {
    SCOPED_TRACE(r.name);
    size_t before = server.log_lines();
    std::string reply = test::exchange(server.port, r.bytes(server), milliseconds(10000));
    EXPECT_EQ(test::status_of(reply), r.status) << reply.substr(0, 200);
    for (int i = 0; i < 200 && server.log_lines() == before; ++i) std::this_thread::sleep_for(milliseconds(5));
    std::vector<std::string> lines = test::lines_of(server.process.err());
    ASSERT_EQ(lines.size(), before + 1) << server.process.err();
    EXPECT_EQ(lines.back().rfind("live: " + std::to_string(r.status) + " ", 0), 0u) << lines.back();
    EXPECT_NE(lines.back().find(r.log), std::string::npos) << lines.back();
    EXPECT_LT(lines.back().size(), 600u);
    std::printf("    %s\n", lines.back().c_str());
  }
  // Stalled requests: a request line, headers and a trickle that never complete.
  test::Probe line(server.port), headers(server.port), trickle(server.port);
  ASSERT_TRUE(line.send("GET /api/sta"));
  ASSERT_TRUE(headers.send("GET /api/state HTTP/1.1\r\nHost: " + server.host + "\r\nX-Slow: "));
  std::thread trickler([&] {
    for (char c : std::string("GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"))
      if (!trickle.send(std::string(1, c))) break;
      else std::this_thread::sleep_for(milliseconds(400));
  });
  // Meanwhile the server answers and the render follows a camera move: each frame request waits for a
  // newer frame than the last one seen, until one shows the moved view (or 30 s pass).
  std::string moved = test::exchange(server.port, server.request("POST", "/api/nav?op=orbit&dx=20&dy=5"));
  ASSERT_EQ(test::status_of(moved), 200) << moved;
  const uint64_t version = nlohmann::json::parse(moved.substr(moved.find("\r\n\r\n") + 4))["version"];
  bool rendered = false;
  uint64_t after = 0;
  const auto deadline = std::chrono::steady_clock::now() + milliseconds(30000);
  while (!rendered && std::chrono::steady_clock::now() < deadline) {
    std::string reply = test::exchange(server.port, server.request("GET", "/api/frame?after=" + std::to_string(after)),
                                       milliseconds(15000));
    if (test::status_of(reply) == 204) continue;
    ASSERT_EQ(test::status_of(reply), 200) << reply.substr(0, 300);
    std::string body = reply.substr(reply.find("\r\n\r\n") + 4);
    uint32_t n = uint8_t(body[0]) | uint8_t(body[1]) << 8 | uint8_t(body[2]) << 16;
    nlohmann::json meta = nlohmann::json::parse(body.substr(4, n));
    after = meta["id"];
    rendered = meta["version"] >= version;
  }
  EXPECT_TRUE(rendered) << "no frame of the moved view";
  EXPECT_EQ(test::status_of(line.read_all(milliseconds(10000))), 408);
  EXPECT_EQ(test::status_of(headers.read_all(milliseconds(10000))), 400);
  EXPECT_EQ(test::status_of(trickle.read_all(milliseconds(10000))), 408);
  trickler.join();
  // Ctrl-C with an idle keep-alive connection and a frame request waiting: both end at once (they would
  // hold the server 5 and 10 s).
  test::Probe idle(server.port), waiting(server.port);
  ASSERT_TRUE(idle.send("GET /api/state HTTP/1.1\r\nHost: " + server.host + "\r\n\r\n"));
  ASSERT_TRUE(waiting.send("GET /api/frame?after=" + std::to_string(uint64_t(1) << 40) +
                           "0 HTTP/1.1\r\nHost: " + server.host + "\r\n\r\n"));
  std::this_thread::sleep_for(milliseconds(200));
  const auto stopping = std::chrono::steady_clock::now();
  test::ProcessResult r = server.process.stop(SIGINT, milliseconds(30000));
  EXPECT_LT(std::chrono::steady_clock::now() - stopping, milliseconds(3000));
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Live view stopped"), std::string::npos) << r.out;
  for (const std::string& l : test::lines_of(r.err)) EXPECT_EQ(l.rfind("live: ", 0), 0u) << l;
  EXPECT_TRUE(server.dir.entries().empty()) << "nothing was written";
}

TEST(HostileRequests, ServeFlagsAreCheckedBeforeAnythingStarts) {
  test::ScratchDir dir;
  struct Case {
    std::vector<std::string> args;
    std::string error;
  };
  for (const Case& c :
       {Case{{"--serve", "65536"}, "error: --serve: port must be an integer from 0 to 65535, got \"65536\""},
        Case{{"--serve=8x"}, "error: --serve: port must be an integer from 0 to 65535, got \"8x\""},
        Case{{"--bind", "0.0.0.0"}, "error: --bind goes with --serve"},
        Case{{"--serve", "0", "--bind", "a b"},
             "error: --bind: expected an address such as 127.0.0.1, ::1 or 0.0.0.0, got \"a b\""},
        Case{{"--serve", "0", "-r", "8192", "4096"},
             "error: --serve: -r 8192 4096: the live view takes 16 to 4096 pixels a side and at most 4194304 pixels"},
        Case{{"--serve", "0", "-r", "8192", "16"},
             "error: --serve: -r 8192 16: the live view takes 16 to 4096 pixels a side and at most 4194304 pixels"},
        Case{{"--serve", "0", "--checkpoint", "c.bin"},
             "error: --serve: --checkpoint is for renders to a file, not the live view"},
        Case{{"--serve", "0", "--engine", "reference"},
             "error: --serve: the live view renders with the wavefront engine and the BVH4 (no --engine or --bvh)"}}) {
    std::vector<std::string> args = c.args;
    args.push_back(PT_DEFAULT_SCENE);
    test::ProcessResult r = test::run_process(PT_PATHTRACER_BINARY, args, dir.path(), 30.0);
    EXPECT_EQ(r.exit_code, 2) << c.args[0];
    EXPECT_EQ(r.err, c.error + "\n");
  }
  // A port in use: one line, exit 1.
  test::BackgroundProcess first(PT_PATHTRACER_BINARY, {"--serve", "0", "-r", "16", "16", PT_DEFAULT_SCENE}, dir.path());
  std::string line = first.wait_for_line("http://127.0.0.1:", milliseconds(30000));
  ASSERT_NE(line.find("127.0.0.1:"), std::string::npos);
  std::string port = std::to_string(std::atoi(line.c_str() + line.find("127.0.0.1:") + 10));
  test::ProcessResult r =
      test::run_process(PT_PATHTRACER_BINARY, {"--serve", port, PT_DEFAULT_SCENE}, dir.path(), 30.0);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err,
            "error: --serve: cannot listen on 127.0.0.1:" + port + " (in use, or not an address of this machine)\n");
  EXPECT_EQ(first.stop(SIGTERM, milliseconds(30000)).exit_code, 0);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(HostileRequests, AServerOnEveryAddressStillAnswersOnlyToThisMachinesNames) {
  test::ScratchDir dir;
  test::BackgroundProcess process(
      PT_PATHTRACER_BINARY, {"--serve", "0", "--bind", "0.0.0.0", "-r", "16", "16", PT_DEFAULT_SCENE}, dir.path());
  std::string line = process.wait_for_line("http://127.0.0.1:", milliseconds(30000));
  ASSERT_NE(line.find("127.0.0.1:"), std::string::npos) << process.err();
  const std::string port = std::to_string(std::atoi(line.c_str() + line.find("127.0.0.1:") + 10));
  char name[256] = "";
  ASSERT_EQ(gethostname(name, sizeof name - 1), 0);
  auto status = [&](const std::string& host) {
    return test::status_of(
        test::exchange(std::stoi(port), "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n"));
  };
  EXPECT_EQ(status("127.0.0.1:" + port), 200);
  EXPECT_EQ(status("LOCALHOST:" + port), 200);
  EXPECT_EQ(status(std::string(name) + ":" + port), 200);
  // A name that an attacker's DNS points at this machine, or the right name on another port, is refused.
  EXPECT_EQ(status("attacker.example:" + port), 403);
  EXPECT_EQ(status("127.0.0.1:1"), 403);
  EXPECT_EQ(status(""), 403);
  test::ProcessResult r = process.stop(SIGINT, milliseconds(30000));
  EXPECT_EQ(r.exit_code, 0);
  std::vector<std::string> lines = test::lines_of(r.err);
  EXPECT_EQ(lines.size(), 3u) << r.err;
  for (const std::string& l : lines) EXPECT_EQ(l.rfind("live: 403 GET /api/state", 0), 0u) << l;
}

}  // namespace
}  // namespace pt
