// Hostile requests to `pathtracer --serve`, through the binary as a user
// runs it, by a scripted client that writes raw bytes: each bad request (bad
// numbers, a NaN camera, a huge view, unknown routes and methods, paths out
// of the start directory, requests without the page's guard, bodies,
// malformed, oversized and stalled requests) gets a 4xx and exactly one log
// line on stderr; the server keeps answering and the render keeps rendering
// meanwhile; Ctrl-C ends it with exit code 0, ending the requests that wait.
// A multipart body that would overflow a 2 MiB thread stack in httplib's
// parser is refused before it is parsed; names that are not UTF-8 (the start
// folder's, the scene file's) survive the JSON. Also the --serve flags that
// must be refused before anything starts, and a server on every address that
// still answers only to this machine's names.
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/http_probe.h"
#include "support/run_process.h"

namespace pt {
namespace {

using std::chrono::milliseconds;

/// `pathtracer --serve 0 -r 32 24 -s 4 SCENE` started in `folder` (or a scratch directory); with `stack_kib`,
/// under `ulimit -s` of that many KiB (which also sets the stack of the threads glibc creates).
struct LiveServerProcess {
  test::ScratchDir dir;
  std::filesystem::path folder;
  test::BackgroundProcess process;
  int port = 0;
  std::string host;

  explicit LiveServerProcess(const std::string& scene = PT_DEFAULT_SCENE, std::filesystem::path in = {},
                             int stack_kib = 0)
      : folder(in.empty() ? dir.path() : in), process(program(stack_kib), arguments(scene, stack_kib), folder) {
    std::string line = process.wait_for_line("http://127.0.0.1:", milliseconds(30000));
    size_t at = line.find("127.0.0.1:");
    if (at != std::string::npos) port = std::atoi(line.c_str() + at + 10);
    host = "127.0.0.1:" + std::to_string(port);
  }
  static std::string program(int stack_kib) { return stack_kib ? "/bin/sh" : PT_PATHTRACER_BINARY; }
  static std::vector<std::string> arguments(const std::string& scene, int stack_kib) {
    std::vector<std::string> args = {"--serve", "0", "-r", "32", "24", "-s", "4", scene};
    if (stack_kib)
      args.insert(args.begin(),
                  {"-c", "ulimit -s " + std::to_string(stack_kib) + " && exec \"$0\" \"$@\"", PT_PATHTRACER_BINARY});
    return args;
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
       431, "request headers larger than 8192 bytes a line"},
      {"headers_of_60_kb",
       [](LiveServerProcess& s) {
         return "GET / HTTP/1.1\r\nHost: " + s.host + "\r\nCookie: " + std::string(60000, 'c') + "\r\n\r\n";
       },
       431, "request headers larger than 8192 bytes a line"},
      {"body_of_1_mb",
       [](LiveServerProcess& s) {
         return "POST /api/settings?samples=2 HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: 1\r\nContent-Type: text/plain\r\nContent-Length: 1000000\r\n\r\n" +
                std::string(100000, 'x');
       },
       413, "a body of 1000000 bytes is not accepted: POST /api/settings takes none"},
      {"form_body",
       [](LiveServerProcess& s) {
         return "POST /api/nav HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: 1\r\nContent-Type: application/x-www-form-urlencoded\r\nContent-Length: 7\r\n"
                "Connection: close\r\n\r\nop=zoom";
       },
       413, "POST /api/nav takes none"},
      {"multipart_body",
       [](LiveServerProcess& s) {
         const std::string part = "--b\r\nContent-Disposition: form-data; name=\"n\"\r\n\r\nv\r\n--b--\r\n";
         return "POST /api/nav?op=still HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: 1\r\nContent-Type: multipart/form-data; boundary=b\r\nContent-Length: " +
                std::to_string(part.size()) + "\r\nConnection: close\r\n\r\n" + part;
       },
       415, "a multipart body is not accepted"},
      {"percent_encoded_host",
       [](LiveServerProcess& s) {
         return "GET /api/state HTTP/1.1\r\nHost: 127%2e0.0.1%3a" + std::to_string(s.port) +
                "\r\nConnection: close\r\n\r\n";
       },
       400, "may not be percent-encoded"},
      {"percent_encoded_guard_header",
       [](LiveServerProcess& s) {
         return "POST /api/nav?op=reset HTTP/1.1\r\nHost: " + s.host +
                "\r\nX-PT-Live: %31\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
       },
       400, "may not be percent-encoded"},
      {"name_read_as_an_option", post("/api/camera/save?name=-rf.txt"), 400, "not starting with '.' or '-'"},
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
       [](LiveServerProcess& s) { return s.request("GET", "/api/state", "Content-Length: 4\r\n") + "abcd"; }, 413,
       "GET /api/state takes none"},
  };
}

TEST(HostileRequests, EachGetsA4xxAndOneLogLineAndTheRenderGoesOn) {
  LiveServerProcess server;
  ASSERT_GT(server.port, 0) << server.process.err();
  for (const HostileRequest& r : hostile_requests()) {
    SCOPED_TRACE(r.name);
    size_t before = server.log_lines();
    std::string reply = test::exchange(server.port, r.bytes(server), milliseconds(30000));
    EXPECT_EQ(test::status_of(reply), r.status) << reply.substr(0, 200);
    EXPECT_EQ(test::header_values(reply, "Connection"), std::vector<std::string>{"close"}) << reply.substr(0, 300);
    EXPECT_TRUE(test::header_values(reply, "Keep-Alive").empty()) << reply.substr(0, 300);
    // The server writes the line before it closes the connection; the pipe brings it soon after.
    ASSERT_TRUE(test::wait_until([&] { return server.log_lines() > before; })) << server.process.err();
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
  EXPECT_EQ(test::status_of(line.read_all(milliseconds(30000))), 408);
  EXPECT_EQ(test::status_of(headers.read_all(milliseconds(30000))), 408);
  EXPECT_EQ(test::status_of(trickle.read_all(milliseconds(30000))), 408);
  trickler.join();
  // Ctrl-C with an idle keep-alive connection and a frame request waiting: the stop ends both (the frame
  // request with 503, where its own wait would end with 204), and the server exits.
  test::Probe idle(server.port), waiting(server.port);
  ASSERT_TRUE(idle.send("GET /api/state HTTP/1.1\r\nHost: " + server.host + "\r\n\r\n"));
  ASSERT_EQ(test::status_of(idle.read_response(milliseconds(30000))), 200);
  // The view complete (4 samples): no frame comes until the next change, so a request for the frame after the
  // newest waits.
  uint64_t newest = 0;
  for (bool complete = false; !complete;) {
    std::string reply = test::exchange(server.port, server.request("GET", "/api/frame?after=" + std::to_string(newest)),
                                       milliseconds(30000));
    if (test::status_of(reply) == 204) continue;
    ASSERT_EQ(test::status_of(reply), 200) << reply.substr(0, 300);
    std::string body = test::body_of(reply);
    uint32_t n = uint8_t(body[0]) | uint8_t(body[1]) << 8 | uint8_t(body[2]) << 16;
    nlohmann::json meta = nlohmann::json::parse(body.substr(4, n));
    newest = meta["id"];
    complete = meta["complete"];
  }
  auto state = [&] {
    std::string reply = test::exchange(server.port, server.request("GET", "/api/state"), milliseconds(30000));
    return nlohmann::json::parse(test::body_of(reply));
  };
  ASSERT_TRUE(waiting.send("GET /api/frame?after=" + std::to_string(newest) + " HTTP/1.1\r\nHost: " + server.host +
                           "\r\n\r\n"));
  ASSERT_TRUE(test::wait_until([&] { return state()["counters"]["frame_waits"] == 1; }));
  test::ProcessResult r = server.process.stop(SIGINT, milliseconds(60000));
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string reply = waiting.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(reply), 503) << reply.substr(0, 300);
  EXPECT_NE(reply.find("the server is stopping"), std::string::npos) << reply;
  EXPECT_EQ(idle.read_all(milliseconds(30000)), "") << "closed without a reply";
  EXPECT_NE(r.out.find("Live view stopped"), std::string::npos) << r.out;
  for (const std::string& l : test::lines_of(r.err)) EXPECT_EQ(l.rfind("live: ", 0), 0u) << l;
  EXPECT_TRUE(server.dir.entries().empty()) << "nothing was written";
}

TEST(HostileRequests, AMultipartBodyIsRefusedBeforeHttplibParsesItUnderA2MiBStack) {
  // httplib parses a multipart part's headers with std::regex, about 300 bytes of stack per byte: a part header
  // of 8000 bytes (it takes lines of up to 8192) needs some 2.4 MB, more than the 2 MiB stack of every thread
  // under `ulimit -s 2048`.
  LiveServerProcess server(PT_DEFAULT_SCENE, {}, 2048);
  ASSERT_GT(server.port, 0) << server.process.err();
  const std::string part =
      "--b\r\nContent-Disposition: form-data; name=\"" + std::string(8000, 'n') + "\"\r\n\r\nv\r\n--b--\r\n";
  std::string reply = test::exchange(server.port,
                                     "POST /api/nav?op=still HTTP/1.1\r\nHost: " + server.host +
                                         "\r\nX-PT-Live: 1\r\nContent-Type: multipart/form-data; boundary=b\r\n"
                                         "Content-Length: " +
                                         std::to_string(part.size()) + "\r\n\r\n" + part,
                                     milliseconds(30000));
  EXPECT_EQ(test::status_of(reply), 415) << reply.substr(0, 300);
  // The server lives on.
  std::string state = test::exchange(server.port, server.request("GET", "/api/state"), milliseconds(30000));
  EXPECT_EQ(test::status_of(state), 200) << state.substr(0, 300);
  test::ProcessResult r = server.process.stop(SIGINT, milliseconds(60000));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> lines = test::lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("live: 415 POST /api/nav?op=still", 0), 0u) << lines[0];
}

TEST(HostileRequests, NamesThatAreNotUtf8SurviveTheJson) {
  // Started in a folder whose name holds byte 0xFF, on a scene file named with the Latin-1 byte 0xE9.
  test::ScratchDir scratch;
  const std::filesystem::path folder = scratch / "\xff";
  std::filesystem::create_directory(folder);
  std::filesystem::copy_file(PT_DEFAULT_SCENE, folder / "sc\xe9.dae");
  LiveServerProcess server((folder / "sc\xe9.dae").string(), folder);
  ASSERT_GT(server.port, 0) << server.process.err();
  // Each byte that is not UTF-8 reaches the JSON as U+FFFD (EF BF BD in UTF-8).
  const std::string shown = (scratch.path() / "\xef\xbf\xbd").string();
  auto json = [&](const std::string& method, const std::string& target, int status) {
    std::string reply = test::exchange(server.port, server.request(method, target), milliseconds(30000));
    EXPECT_EQ(test::status_of(reply), status) << method << " " << target << ": " << reply.substr(0, 300);
    return nlohmann::json::parse(test::body_of(reply), nullptr, false);
  };
  EXPECT_EQ(json("GET", "/api/state", 200)["scene"], "sc\xef\xbf\xbd.dae");
  EXPECT_EQ(json("POST", "/api/camera/save?name=u.txt", 200)["file"], shown + "/u.txt");
  EXPECT_EQ(json("POST", "/api/render?name=u.png", 202)["file"], shown + "/u.png");
  nlohmann::json job;
  ASSERT_TRUE(test::wait_until([&] { return (job = json("GET", "/api/render", 200))["state"] != "rendering"; }));
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_EQ(json("GET", "/api/state", 200)["job"]["file"], shown + "/u.png");
  test::ProcessResult r = server.process.stop(SIGINT, milliseconds(60000));
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(std::filesystem::exists(folder / "u.txt"));
  EXPECT_TRUE(std::filesystem::exists(folder / "u.png"));
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
