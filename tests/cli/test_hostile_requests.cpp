// Hostile clients of `pathtracer --serve`, through the binary as a user runs
// it, by a scripted client that writes raw bytes (the hostile requests
// themselves are tested in process: tests/live/test_live_server.cpp): a
// refused request is one line on stderr; Ctrl-C ends the server with exit
// code 0 whatever its clients do (idle, waiting, stalled, not reading),
// answering the requests that wait; under 2 MiB thread stacks a multipart
// body is refused and the server lives on; names that are not UTF-8 (the
// start folder's, the scene file's) survive the JSON and name the files
// written. Also the --serve flags that must be refused before anything
// starts, and a server on every address that still answers only to this
// machine's names.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
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
  /// A request as the page makes it.
  std::string request(const std::string& method, const std::string& target) {
    return method + " " + target + " HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n" +
           (method == "POST" ? "Content-Length: 0\r\n" : "") + "Connection: close\r\n\r\n";
  }
};

/// The view complete (4 samples): no frame comes until the next change; the newest frame's id.
uint64_t newest_frame(LiveServerProcess& server) {
  for (uint64_t newest = 0;;) {
    std::string reply = test::exchange(server.port, server.request("GET", "/api/frame?after=" + std::to_string(newest)),
                                       milliseconds(30000));
    if (test::status_of(reply) == 204) continue;
    EXPECT_EQ(test::status_of(reply), 200) << reply.substr(0, 300);
    std::string body = test::body_of(reply);
    if (body.size() < 4) return newest;
    uint32_t n = uint8_t(body[0]) | uint8_t(body[1]) << 8 | uint8_t(body[2]) << 16;
    nlohmann::json meta = nlohmann::json::parse(body.substr(4, n));
    newest = meta["id"];
    if (meta["complete"]) return newest;
  }
}

TEST(HostileRequests, ARefusalIsOneLineOnStderrAndCtrlCEndsTheServerWhateverItsClientsDo) {
  LiveServerProcess server;
  ASSERT_GT(server.port, 0) << server.process.err();
  // A refused request: its 4xx, one Connection: close, one line on stderr (the hostile requests themselves are
  // tests/live/test_live_server.cpp's, in process).
  std::string refused = test::exchange(server.port, server.request("POST", "/api/nav?op=orbit&dx=NaN&dy=1"));
  EXPECT_EQ(test::status_of(refused), 400) << refused.substr(0, 200);
  EXPECT_EQ(test::header_values(refused, "Connection"), std::vector<std::string>{"close"});
  ASSERT_TRUE(test::wait_until([&] { return server.log_lines() == 1; })) << server.process.err();
  EXPECT_EQ(test::lines_of(server.process.err())[0].rfind("live: 400 POST /api/nav?op=orbit&dx=NaN&dy=1 from ", 0), 0u)
      << server.process.err();
  // Ctrl-C with an idle keep-alive connection, a frame request waiting, a request that never ends and a client
  // that asks for the page three hundred times without reading (its responses stall): the stop ends them all
  // (the frame request with 503, where its own wait would end with 204), and the server exits with 0.
  test::Probe idle(server.port), waiting(server.port), stalled(server.port), unread(server.port);
  ASSERT_TRUE(idle.send("GET /api/state HTTP/1.1\r\nHost: " + server.host + "\r\nX-PT-Live: 1\r\n\r\n"));
  ASSERT_EQ(test::status_of(idle.read_response(milliseconds(30000))), 200);
  const uint64_t newest = newest_frame(server);
  ASSERT_TRUE(waiting.send("GET /api/frame?after=" + std::to_string(newest) + " HTTP/1.1\r\nHost: " + server.host +
                           "\r\nX-PT-Live: 1\r\n\r\n"));
  ASSERT_TRUE(stalled.send("GET /api/sta"));
  std::string pages;
  for (int i = 0; i < 300; ++i) pages += "GET /app.js HTTP/1.1\r\nHost: " + server.host + "\r\n\r\n";
  ASSERT_TRUE(unread.send(pages));
  auto counters = [&] {
    std::string reply = test::exchange(server.port, server.request("GET", "/api/state"), milliseconds(30000));
    return nlohmann::json::parse(test::body_of(reply))["counters"];
  };
  ASSERT_TRUE(test::wait_until([&] { return counters()["frame_waits"] == 1; }));
  test::ProcessResult r = server.process.stop(SIGINT, milliseconds(60000));
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string reply = waiting.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(reply), 503) << reply.substr(0, 300);
  EXPECT_NE(reply.find("the server is stopping"), std::string::npos) << reply;
  EXPECT_EQ(idle.read_all(milliseconds(30000)), "") << "closed without a reply";
  EXPECT_EQ(stalled.read_all(milliseconds(30000)), "");
  EXPECT_NE(r.out.find("Live view stopped"), std::string::npos) << r.out;
  EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
  EXPECT_TRUE(server.dir.entries().empty()) << "nothing was written";
}

TEST(HostileRequests, AMultipartBodyUnderA2MiBStackIsRefusedAndTheServerLivesOn) {
  // Every thread's stack is 2 MiB under `ulimit -s 2048`; a multipart body with an 8000-byte part header is
  // refused before it is read (no request has a body).
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
  EXPECT_EQ(test::status_of(reply), 413) << reply.substr(0, 300);
  // The server lives on.
  std::string state = test::exchange(server.port, server.request("GET", "/api/state"), milliseconds(30000));
  EXPECT_EQ(test::status_of(state), 200) << state.substr(0, 300);
  test::ProcessResult r = server.process.stop(SIGINT, milliseconds(60000));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> lines = test::lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("live: 413 POST /api/nav?op=still", 0), 0u) << lines[0];
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
  std::vector<std::string> written;
  for (const auto& e : std::filesystem::directory_iterator(folder)) written.push_back(e.path().filename());
  std::sort(written.begin(), written.end());
  EXPECT_EQ(written, (std::vector<std::string>{"sc\xe9.dae", "u.png", "u.txt"}))
      << "under their own names, nothing else";
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
    return test::status_of(test::exchange(
        std::stoi(port), "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nConnection: close\r\n\r\n"));
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
