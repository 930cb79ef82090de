// The live view's HTTP server in process, with small limits and a clock that
// moves only when a test moves it (no deadline passes by itself, so every
// test decides on events): the page and the API answer well-formed requests;
// hostile ones (bad numbers, NaN cameras, huge views, unknown routes, paths
// out of the start directory, missing guard headers, another site's
// requests, NUL bytes, bodies, oversized or malformed requests, partial
// requests that stall, too many connections from one client) each get a 4xx
// (or are closed) and exactly one log line, and meanwhile the server goes on
// answering, every client keeps its share of the connections, and the render
// goes on rendering. Keep-alive answers say what the server then does, and
// a stop ends every connection at once.
#include <algorithm>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <future>
#include <mutex>
#include <thread>

#include "live_server_fixture.h"

namespace pt::live {
namespace {

using namespace test_server;

class LiveServer : public LiveServerBase {
 protected:
  LiveServer() : LiveServerBase({small_limits()}) {}
};

TEST_F(LiveServer, ServesTheEmbeddedPageWithItsGuardHeaders) {
  Reply page = GET("/");
  EXPECT_EQ(page.status(), 200);
  EXPECT_EQ(page.header("Content-Type"), std::vector<std::string>{"text/html; charset=utf-8"});
  EXPECT_NE(page.body().find("<canvas id=\"image\""), std::string::npos);
  ASSERT_EQ(page.header("Content-Security-Policy").size(), 1u);
  EXPECT_NE(page.header("Content-Security-Policy")[0].find("default-src 'none'"), std::string::npos);
  EXPECT_EQ(page.header("X-Content-Type-Options"), std::vector<std::string>{"nosniff"});
  for (const char* asset : {"/app.js", "/style.css"}) {
    Reply r = GET(asset);
    EXPECT_EQ(r.status(), 200) << asset;
    EXPECT_GT(r.body().size(), 1000u) << asset;
  }
  // HEAD: the head alone.
  Reply head = send("HEAD / HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(head.status(), 200);
  EXPECT_EQ(head.header("Content-Length"), std::vector<std::string>{std::to_string(page.body().size())});
  EXPECT_EQ(head.body(), "");
  EXPECT_TRUE(log_lines().empty());
}

TEST_F(LiveServer, StateFramesAndMovesWork) {
  nlohmann::json s = GET("/api/state").json();
  EXPECT_EQ(s["settings"]["width"], options_.width);
  EXPECT_EQ(s["isa"], std::string(isa_name(bvh.isa())));
  Reply frame = GET("/api/frame?after=0");
  ASSERT_EQ(frame.status(), 200);
  size_t pixels = 0;
  nlohmann::json meta = frame_meta(frame.body(), &pixels);
  EXPECT_EQ(pixels, size_t(meta["width"].get<int>()) * meta["height"].get<int>() * 4);
  Reply moved = POST("/api/nav?op=orbit&dx=12.5&dy=-3");
  ASSERT_EQ(moved.status(), 200);
  const uint64_t version = moved.json()["version"];
  // The next frames show the moved view.
  uint64_t after = meta["id"];
  for (int i = 0; i < 50; ++i) {
    Reply f = GET("/api/frame?after=" + std::to_string(after));
    ASSERT_EQ(f.status(), 200);
    nlohmann::json fm = frame_meta(f.body());
    after = fm["id"];
    if (fm["version"] == version) return;
  }
  ADD_FAILURE() << "no frame of the moved view";
}

TEST_F(LiveServer, HostileRequestsGetA4xxAndOneLogLine) {
  expect_refused(get("/nope"), 404, "no such route");
  expect_refused(get("/../../etc/passwd"), 404);
  expect_refused(get("/%2e%2e/%2e%2e/etc/passwd"), 404);
  expect_refused(get("/app.js?x=1"), 400, "no parameters");
  expect_refused(get("/api/state?evil=1"), 400, "unknown parameter");
  expect_refused(post("/api/nav?op=orbit&dx=nan&dy=0"), 400, "dx: must be a number");
  expect_refused(post("/api/nav?op=orbit&dx=1e999&dy=0"), 400, "dx: must be a number");
  expect_refused(post("/api/nav?op=pan&dx=1&dy=-inf"), 400, "dy: must be a number");
  expect_refused(post("/api/nav?op=orbit&dx=1&dx=2&dy=0"), 400, "more than once");
  expect_refused(post("/api/nav?op=fly"), 400, "op: must be one of orbit, pan, zoom, reset");
  expect_refused(post("/api/nav?op=zoom&steps=1e6"), 400, "steps");
  expect_refused(post("/api/nav?op=zoom&steps=0x10"), 400, "steps: must be a number");
  expect_refused(post("/api/camera?position=nan,0,0&target=0,0,0"), 400, "position");
  expect_refused(post("/api/camera?position=1e30,0,0&target=0,0,0"), 400, "position");
  expect_refused(post("/api/camera?position=1,1,1&target=1,1,1"), 400, "apart");
  expect_refused(post("/api/camera?position=0,0,1e9&target=0,0,0"), 400, "apart");  // beyond max_r: not clamped
  // Beyond the reach of the scene's centre (100 diagonals), as a pan stops: floats would lose the view there.
  expect_refused(post("/api/camera?position=0,0,1001&target=0,0,1000"), 400, "the target must lie within");
  expect_refused(post("/api/camera?position=0,5,0&target=0,0,0"), 400, "straight above or below");
  expect_refused(post("/api/camera?position=0,0,5&target=0,0,0&vfov=180"), 400, "vfov");
  expect_refused(post("/api/settings?width=100000"), 400, "width: must be an integer from 16 to 4096");
  expect_refused(post("/api/settings?width=1000000000000"), 400, "width: must be an integer from 16 to 4096");
  expect_refused(post("/api/settings?width=4096&height=4096"), 400, "at most 4194304 pixels");
  expect_refused(post("/api/settings?samples=0"), 400, "samples");
  expect_refused(post("/api/settings?display=wireframe"), 400, "display");
  expect_refused(get("/api/frame?after=-1"), 400, "after");
  expect_refused(get("/api/bvh/level?depth=1000"), 400, "depth");
  expect_refused(get("/api/bvh/walk?x=1e9&y=0"), 400, "x");
  expect_refused(post("/api/camera/save?name=../evil.txt"), 400, "name");
  expect_refused(post("/api/camera/save?name=%2Fetc%2Fevil.txt"), 400, "name");
  expect_refused(post("/api/camera/save?name=..%2F..%2Fcam.txt"), 400, "name: must be");
  expect_refused(post("/api/render?name=x.sh"), 400, "name");
  expect_refused(post("/api/render?name=sub%2Fx.png"), 400, "name: must be");
  // A name a shell would read as an option.
  expect_refused(post("/api/camera/save?name=-rf.txt"), 400, "not starting with '.' or '-'");
  expect_refused(post("/api/render?name=--help.png"), 400, "not starting with '.' or '-'");
  // The guard: an API request without the page's header, another site's Host, no Host, another method.
  const std::string close = "Connection: close\r\n\r\n";
  expect_refused("POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host + "\r\nContent-Length: 0\r\n" + close, 403,
                 "X-PT-Live");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\n" + close, 403, "X-PT-Live");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: evil.example:80\r\nX-PT-Live: 1\r\n" + close, 403, "evil.example");
  expect_refused("GET / HTTP/1.1\r\n" + close, 403, "Host");
  expect_refused("DELETE /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n" + close, 405,
                 "method DELETE is not used here");
  // Header values are taken as sent: percent-encoded, the guard's headers do not match.
  std::string encoded_host = host;
  encoded_host.replace(encoded_host.find(':'), 1, "%3a");
  encoded_host.replace(encoded_host.find('.'), 1, "%2e");
  expect_refused("GET /api/state HTTP/1.1\r\nHost: " + encoded_host + "\r\nX-PT-Live: 1\r\n" + close, 403,
                 "is not this server's address");
  expect_refused("POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: %31\r\n" + close, 403,
                 "X-PT-Live");
  // Another site's request, even with the header (a browser would not send it there without a preflight).
  expect_refused(
      "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nOrigin: http://evil.example\r\n" + close, 403,
      "Origin \"http://evil.example\" is another site");
  expect_refused(
      "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nSec-Fetch-Site: cross-site\r\n" + close, 403,
      "Sec-Fetch-Site \"cross-site\"");
  // A NUL inside a header value would end the value the guard sees early.
  expect_refused(std::string("GET /api/state HTTP/1.1\r\nHost: ") + host + std::string("\0.evil.example", 14) +
                     "\r\nX-PT-Live: 1\r\n" + close,
                 400, "without NUL bytes");
  expect_refused("POST /api/nav?op=reset HTTP/1.1\r\nHost: " + host + std::string("\r\nX-PT-Live: 1\0x", 16) +
                     "\r\nContent-Length: 0\r\n" + close,
                 400, "without NUL bytes");
  expect_refused("GET /api/state HTTP/1.1\nHost: " + host + "\nX-PT-Live: 1\nConnection: close\n\n", 400,
                 "ending in CRLF");
  // Oversized requests: a connection holds 64 KiB (libmicrohttpd answers, the server logs).
  expect_refused("GET / HTTP/1.1\r\nHost: " + host + "\r\nX-Long: " + std::string(70000, 'b') + "\r\n\r\n", 431,
                 "request headers larger than a connection's memory");
  expect_refused("GET / HTTP/1.1\r\nHost: " + host + "\r\nCookie: " + std::string(60000, 'b') + "\r\n\r\n", 431,
                 "request headers larger");
  std::string many_headers = "GET / HTTP/1.1\r\nHost: " + host + "\r\n";
  for (int i = 0; i < 2000; ++i) many_headers += "X-" + std::to_string(i) + ": " + std::string(40, 'd') + "\r\n";
  expect_refused(many_headers + "\r\n", 431, "request headers larger");
  // Nothing was written outside the start directory, nor in it.
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_FALSE(std::filesystem::exists(dir.path().parent_path() / "evil.txt"));
  for (const std::string& line : log_lines()) std::printf("    %s\n", line.c_str());
}

TEST_F(LiveServer, BytesThatAreNoRequestAreClosedAndTheServerGoesOn) {
  // No request line to name: libmicrohttpd closes the connection (garbage, TLS) or answers 414 (a line longer
  // than a connection holds) before the server sees a request, so there is no log line.
  EXPECT_EQ(send("GARBAGE\r\n\r\n").raw, "");
  EXPECT_EQ(send(std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03\r\n\r\n", 15)).raw, "");
  Reply long_line = send("GET /" + std::string(70000, 'a') + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n");
  EXPECT_EQ(long_line.status(), 414);
  EXPECT_EQ(long_line.header("Connection"), std::vector<std::string>{"close"});
  EXPECT_EQ(GET("/api/state").status(), 200);
  EXPECT_TRUE(log_lines().empty()) << log_lines().front();
}

TEST_F(LiveServer, ARangeHeaderGetsTheWholeBodyOnce) {
  // Responses are sent whole: a Range of two thousand parts is one copy of the frame, not two thousand.
  std::string ranges = "bytes=0-";
  while (ranges.size() < 7000) ranges += ",0-";
  Reply frame = send("GET /api/frame?after=0 HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nRange: " + ranges +
                     "\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(frame.status(), 200);
  size_t pixels = 0;
  nlohmann::json meta = frame_meta(frame.body(), &pixels);
  EXPECT_EQ(pixels, size_t(meta["width"].get<int>()) * meta["height"].get<int>() * 4);
  EXPECT_EQ(frame.header("Content-Length"), std::vector<std::string>{std::to_string(frame.body().size())});
  EXPECT_TRUE(log_lines().empty());
}

TEST_F(LiveServer, RequestBodiesAreRefusedBeforeTheyAreRead) {
  const std::string close = "Connection: close\r\n\r\n";
  const std::string head = "POST /api/nav?op=still HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n";
  // Chunks of 4 KiB, 30 KiB in all.
  std::string chunked;
  for (int i = 0; i < 30; ++i) chunked += "400\r\n" + std::string(1024, 'x') + "\r\n";
  expect_refused(head + "Transfer-Encoding: chunked\r\n" + close + chunked + "0\r\n\r\n", 411,
                 "Transfer-Encoding is not accepted");
  expect_refused(head + "Content-Length: 3\r\nContent-Length: 3\r\n" + close + "abc", 400, "more than once");
  // No route reads a body: one of any size or kind is refused (a form's, a compressed one, a multipart one).
  expect_refused(head + "Content-Length: 1\r\n" + close + "b", 413,
                 "a body of 1 bytes is not accepted: POST /api/nav takes none");
  expect_refused(head + "Content-Length: 1000000\r\n" + close + std::string(100000, 'y'), 413, "1000000 bytes");
  expect_refused(
      head + "Content-Type: application/x-www-form-urlencoded\r\nContent-Length: 9\r\n" + close + "op=orbit&", 413,
      "takes none");
  expect_refused(head + "Content-Encoding: gzip\r\nContent-Length: 10\r\n" + close + std::string(10, 'z'), 413,
                 "takes none");
  const std::string part =
      "--b\r\nContent-Disposition: form-data; name=\"" + std::string(8000, 'n') + "\"\r\n\r\nv\r\n--b--\r\n";
  expect_refused(head + "Content-Type: multipart/form-data; boundary=b\r\nContent-Length: " +
                     std::to_string(part.size()) + "\r\n" + close + part,
                 413, "takes none");
  expect_refused(head + "Expect: 100-continue\r\nContent-Length: 5\r\n" + close + "hello", 413, "takes none");
  expect_refused(
      "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\nContent-Length: 5\r\n" + close + "hello", 413,
      "GET /api/state takes none");
  // A refused request's body is left unread, so its connection closes instead of reading the body as a request.
  test::Probe probe(port);
  ASSERT_TRUE(
      probe.send("POST /api/nav?op=still HTTP/1.1\r\nHost: evil.example\r\nX-PT-Live: 1\r\n"
                 "Content-Length: 37\r\n\r\nGET /api/state HTTP/1.1\r\nHost: x\r\n\r\n"));
  std::string reply = probe.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(reply), 413);
  EXPECT_EQ(reply.find("HTTP/1.1", 10), std::string::npos) << reply;
  // Without a body (no Content-Length, or 0 in any number of digits), a POST is fine.
  EXPECT_EQ(POST("/api/nav?op=still").status(), 200);
  EXPECT_EQ(send(head + "Content-Length: 000\r\n" + close).status(), 200);
  EXPECT_EQ(send(head + close).status(), 200);
}

TEST_F(LiveServer, KeepAliveAnswersSayWhatTheServerThenDoes) {
  // HTTP/1.1: kept alive without a word (no Connection, no Keep-Alive header), and the next request is served.
  test::Probe kept(port);
  const std::string state = "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n\r\n";
  ASSERT_TRUE(kept.send(state));
  std::string first = kept.read_response(milliseconds(30000));
  EXPECT_EQ(test::status_of(first), 200);
  EXPECT_TRUE(test::header_values(first, "Connection").empty()) << first.substr(0, 400);
  EXPECT_TRUE(test::header_values(first, "Keep-Alive").empty()) << first.substr(0, 400);
  ASSERT_TRUE(kept.send(state));
  EXPECT_EQ(test::status_of(kept.read_response(milliseconds(30000))), 200);
  // A refusal on it says close, once, without Keep-Alive, and closes.
  ASSERT_TRUE(kept.send("POST /api/nav?op=fly HTTP/1.1\r\nHost: " + host +
                        "\r\nX-PT-Live: 1\r\nContent-Length: 0\r\nConnection: keep-alive\r\n\r\n"));
  std::string refused = kept.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(refused), 400);
  EXPECT_EQ(test::header_values(refused, "Connection"), std::vector<std::string>{"close"}) << refused;
  EXPECT_TRUE(test::header_values(refused, "Keep-Alive").empty()) << refused;
  // HTTP/1.0 asking in lower case to keep the connection: the answer says it is kept, and it is.
  test::Probe old(port);
  const std::string old_state = "GET /api/state HTTP/1.0\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n";
  ASSERT_TRUE(old.send(old_state + "Connection: keep-alive\r\n\r\n"));
  std::string kept_old = old.read_response(milliseconds(30000));
  EXPECT_EQ(test::status_of(kept_old), 200);
  EXPECT_EQ(test::header_values(kept_old, "Connection"), std::vector<std::string>{"Keep-Alive"}) << kept_old;
  EXPECT_TRUE(test::header_values(kept_old, "Keep-Alive").empty()) << kept_old;
  // Not asking: the answer says close, and the connection closes after it.
  ASSERT_TRUE(old.send(old_state + "\r\n"));
  std::string last = old.read_all(milliseconds(30000));
  EXPECT_EQ(test::status_of(last), 200);
  EXPECT_EQ(test::header_values(last, "Connection"), std::vector<std::string>{"close"}) << last;
  EXPECT_EQ(last.find("HTTP/1.", 10), std::string::npos) << "one answer, then the end of the connection";
}

TEST_F(LiveServer, CrossSiteRequestsAreRefusedBeforeTheyHoldAWaitOrAConnection) {
  // Six frame waits from another site's page, as a browser sends them (Origin, no X-PT-Live), from the user's
  // own address, each on a connection it keeps open: each is refused at once and its connection closed.
  const uint64_t last = complete_view();
  const std::string target = "/api/frame?after=" + std::to_string(last);
  std::vector<std::unique_ptr<test::Probe>> evil;
  for (int i = 0; i < 6; ++i) {
    evil.push_back(std::make_unique<test::Probe>(port));
    ASSERT_TRUE(evil.back()->send("GET " + target + " HTTP/1.1\r\nHost: " + host +
                                  "\r\nOrigin: http://evil.example\r\nSec-Fetch-Site: cross-site\r\n\r\n"));
  }
  for (auto& p : evil) EXPECT_EQ(test::status_of(p->read_all(milliseconds(30000))), 403);
  EXPECT_EQ(log_count("live: 403 GET " + target), 6u);
  EXPECT_EQ(server.shares().frame_waits(), 0u);
  ASSERT_TRUE(test::wait_until([this] { return server.shares().held_by("127.0.0.1") == 0; }));
  // The page's own frame request waits (within its client's share of 2), and gets the next frame.
  test::Probe page(port);
  ASSERT_TRUE(page.send("GET " + target + " HTTP/1.1\r\nHost: " + host +
                        "\r\nX-PT-Live: 1\r\nSec-Fetch-Site: same-origin\r\nConnection: close\r\n\r\n"));
  ASSERT_TRUE(test::wait_until([this] { return server.shares().frame_waits() == 1; }));
  EXPECT_EQ(POST("/api/nav?op=orbit&dx=3&dy=0").status(), 200);
  Reply frame{page.read_all(milliseconds(30000))};
  EXPECT_EQ(frame.status(), 200);
  EXPECT_GT(frame_meta(frame.body())["id"].get<uint64_t>(), last);
}

TEST_F(LiveServer, StopEndsEveryConnectionAtOnce) {
  // An idle keep-alive connection, a frame request waiting for a frame, a request that never ends, and a client
  // that asks for the page three hundred times and never reads: its responses fill the sockets and stall. On the
  // server's clock no deadline passes, so a stop that waited for one would not end; the frame wait (a minute)
  // would end with 204, not 503.
  test::Probe idle(port), waiting(port), stalled(port), unread(port);
  ASSERT_TRUE(idle.send("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n\r\n"));
  ASSERT_EQ(test::status_of(idle.read_response(milliseconds(30000))), 200);
  const uint64_t last = complete_view();
  ASSERT_TRUE(waiting.send("GET /api/frame?after=" + std::to_string(last) + " HTTP/1.1\r\nHost: " + host +
                           "\r\nX-PT-Live: 1\r\n\r\n"));
  ASSERT_TRUE(stalled.send("GET /api/sta"));
  std::string pages;
  for (int i = 0; i < 300; ++i) pages += "GET /app.js HTTP/1.1\r\nHost: " + host + "\r\n\r\n";
  ASSERT_TRUE(unread.send(pages));
  ASSERT_TRUE(test::wait_until([this] {
    return server.shares().frame_waits() == 1 && server.shares().in_phase(ClientShares::Phase::kWriting) == 1;
  }));
  auto stopping = std::async(std::launch::async, [this] {
    server.stop();  // as serve_live_view stops: the server, then the render
    session.stop();
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
  ASSERT_EQ(POST("/api/nav?op=orbit&dx=3&dy=0").status(), 200);
  Reply frame = GET("/api/frame?after=" + std::to_string(newest));
  EXPECT_EQ(frame.status(), 500);
  EXPECT_NE(frame.body().find("the render of this view failed: std::bad_alloc"), std::string::npos) << frame.body();
  std::vector<std::string> lines = log_lines();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].rfind("live: the render of view ", 0), 0u) << lines[0];
  EXPECT_EQ(lines[1].rfind("live: 500 GET /api/frame", 0), 0u) << lines[1];
  EXPECT_NE(GET("/api/state").json()["render_error"].get<std::string>().find("bad_alloc"), std::string::npos);
  // The server goes on, and the next change renders.
  ASSERT_EQ(POST("/api/nav?op=orbit&dx=3&dy=0").status(), 200);
  EXPECT_EQ(GET("/api/frame?after=" + std::to_string(newest)).status(), 200);
}

TEST_F(LiveServer, StalledRequestsAreClosedAtTheirDeadlinesWhileOthersAreServed) {
  // A request line that never ends (the connection idles: 1000 ms), headers that never end and headers that
  // trickle in (400 ms from the request line: the deadline is for all of them, however the bytes come).
  test::Probe partial_line(port), partial_headers(port), trickle(port);
  ASSERT_TRUE(partial_line.send("GET /api/sta"));
  ASSERT_TRUE(partial_headers.send("GET /api/state HTTP/1.1\r\nHost: " + host + "\r\nX-Wait: "));
  ASSERT_TRUE(trickle.send("GET /api/state HTTP/1.1\r\n"));
  ASSERT_TRUE(test::wait_until([this] { return server.shares().in_phase(ClientShares::Phase::kReading) == 2; }));
  EXPECT_EQ(GET("/api/state").status(), 200);  // meanwhile
  EXPECT_EQ(log_count("live: closed"), 0u) << "no deadline has passed on the server's clock";
  for (char ch : std::string("Host: ") + host + "\r\nX-Slow: abcdefgh") {
    if (!trickle.send(std::string(1, ch))) break;  // closed: its deadline passed
    clock.advance(milliseconds(25));
  }
  clock.advance(milliseconds(1000));
  EXPECT_EQ(partial_line.read_all(milliseconds(30000)), "");
  EXPECT_EQ(partial_headers.read_all(milliseconds(30000)), "");
  EXPECT_EQ(trickle.read_all(milliseconds(30000)), "");
  // The two mid-request are logged (just after they close); a connection that idles out is not (an idle
  // keep-alive does as much).
  EXPECT_TRUE(test::wait_until([this] { return log_count("live: closed the connection of 127.0.0.1:") == 2; }));
  EXPECT_EQ(log_count("no complete request within 400 ms"), 2u);
  EXPECT_EQ(log_lines().size(), 2u);
}

TEST_F(LiveServer, AClientBeyondItsShareIsRefusedAndAClientWithinItTakesAConnectionOfTheHeaviest) {
  // 127.0.0.1 takes its share, 6 of the 8 connections; a seventh is closed at once.
  std::vector<std::unique_ptr<test::Probe>> heavy;
  for (int i = 0; i < 6; ++i) heavy.push_back(std::make_unique<test::Probe>(port, "127.0.0.1"));
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 6; }));
  EXPECT_EQ(send(get("/api/state"), "127.0.0.1").raw, "");
  EXPECT_EQ(log_count("live: refused a connection from 127.0.0.1:"), 1u);
  EXPECT_EQ(log_count("127.0.0.1 has 6 connections open, as many as one client may"), 1u);
  // 127.0.0.2 takes the last two: the server is full.
  test::Probe second_a(port, "127.0.0.2"), second_b(port, "127.0.0.2");
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 8; }));
  // 127.0.0.3 is served all the same: its connection takes one of 127.0.0.1's idle ones.
  EXPECT_EQ(send(get("/api/state"), "127.0.0.3").status(), 200);
  EXPECT_EQ(log_count("live: a connection of 127.0.0.1 closed for one of 127.0.0.3"), 1u);
  EXPECT_EQ(server.shares().held_by("127.0.0.1"), 5u);
  // So is 127.0.0.2 with a third connection (it holds 2, 127.0.0.1 holds 5).
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 7; }));
  test::Probe second_c(port, "127.0.0.2");
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 8; }));
  EXPECT_EQ(send(get("/api/state"), "127.0.0.2").status(), 200);
  EXPECT_EQ(log_count("live: a connection of 127.0.0.1 closed for one of 127.0.0.2"), 1u);
  EXPECT_EQ(server.shares().held_by("127.0.0.1"), 4u);
  // Once the connections close, service is as before.
  heavy.clear();
  ASSERT_TRUE(test::wait_until([this] { return server.open_connections() == 3; }));
  EXPECT_EQ(GET("/api/state").status(), 200);
}

TEST_F(LiveServer, FrameRequestsBeyondAClientsShareGet429) {
  const uint64_t last = complete_view();
  const std::string wait =
      "GET /api/frame?after=" + std::to_string(last) + " HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n\r\n";
  test::Probe first(port), second(port), other(port, "127.0.0.2");
  ASSERT_TRUE(first.send(wait));
  ASSERT_TRUE(second.send(wait));
  ASSERT_TRUE(test::wait_until([this] { return server.shares().frame_waits() == 2; }));
  Reply refused = GET("/api/frame?after=" + std::to_string(last));
  EXPECT_EQ(refused.status(), 429) << refused.raw.substr(0, 300);
  EXPECT_NE(refused.body().find("this client has 2 frame requests waiting already"), std::string::npos);
  // Another client has its own share; and the next frame answers every waiting request.
  ASSERT_TRUE(other.send(wait));
  ASSERT_TRUE(test::wait_until([this] { return server.shares().frame_waits() == 3; }));
  ASSERT_EQ(POST("/api/nav?op=orbit&dx=3&dy=0").status(), 200);
  for (test::Probe* p : {&first, &second, &other})
    EXPECT_EQ(test::status_of(p->read_response(milliseconds(30000))), 200);
  EXPECT_EQ(log_count("live: 429"), 1u);
}

/// The server at the product's limits (48 connections, 16 per client, 6 frame waits per client).
class LiveServerAtProductLimits : public LiveServerBase {
 protected:
  LiveServerAtProductLimits() : LiveServerBase({ServerLimits{}}) {}

  /// The page, the state and a frame, each on a new connection from 127.0.0.1: their statuses.
  std::vector<int> visit() {
    std::vector<int> statuses;
    for (const char* target : {"/", "/api/state", "/api/frame?after=0"})
      statuses.push_back(send(get(target), "127.0.0.1").status());
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
  const std::string request = "GET /api/render HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n\r\n";
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
  const std::string request = "GET /api/render HTTP/1.1\r\nHost: " + host + "\r\nX-PT-Live: 1\r\n\r\n";
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
  EXPECT_EQ(log_count("no complete request within"), 0u);
}

TEST_F(LiveServer, FilesAreWrittenOnlyIntoTheStartDirectoryUnderTheirNames) {
  Reply saved = POST("/api/camera/save?name=my_view.txt");
  ASSERT_EQ(saved.status(), 200) << saved.body();
  EXPECT_EQ(saved.json()["file"], (dir / "my_view.txt").string());
  EXPECT_EQ(format_camera_settings(read_camera_settings_file(dir / "my_view.txt")),
            format_camera_settings(session.view().camera));
  ASSERT_EQ(POST("/api/camera/save").status(), 200);
  EXPECT_TRUE(std::filesystem::exists(dir / "camera.txt"));
  Reply small = POST("/api/settings?samples=2");
  ASSERT_EQ(small.status(), 200);
  Reply render = POST("/api/render?name=shot.png");
  ASSERT_EQ(render.status(), 202) << render.body();
  nlohmann::json job;
  ASSERT_TRUE(test::wait_until([&] {
    job = GET("/api/render").json();
    return job["state"] != "rendering";
  }));
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_TRUE(std::filesystem::exists(dir / "shot.png"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"camera.txt", "my_view.txt", "shot.png"}));
}

TEST_F(LiveServer, ASavedCameraHasTheScreenFieldsOfTheViewsSizeNow) {
  ASSERT_EQ(POST("/api/settings?width=96&height=36").status(), 200);
  ASSERT_EQ(POST("/api/camera/save?name=wide.txt").status(), 200);
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
  ASSERT_EQ(POST("/api/settings?samples=2&adaptive_tolerance=0.5&adaptive_batch=1").status(), 200);
  expect_refused(post("/api/render?name=shot.png"), 409, "shot_rate.png exists");
  EXPECT_EQ(read("taken.txt"), "mine");
  EXPECT_EQ(read("taken.png"), "mine");
  EXPECT_EQ(read("shot_rate.png"), "mine");
  // A new name is written, once: the second save of it is refused.
  ASSERT_EQ(POST("/api/camera/save?name=new.txt").status(), 200);
  expect_refused(post("/api/camera/save?name=new.txt"), 409, "new.txt exists");
  // The default files are the command line's: saved again, they are replaced.
  ASSERT_EQ(POST("/api/camera/save").status(), 200);
  ASSERT_EQ(POST("/api/camera/save").status(), 200);
  EXPECT_EQ(dir.entries(),
            (std::vector<std::string>{"camera.txt", "new.txt", "shot_rate.png", "taken.png", "taken.txt"}));
}

TEST_F(LiveServer, ARenderJobWhoseNameAppearsMeanwhileFailsAndReplacesNothing) {
  ASSERT_EQ(POST("/api/settings?samples=64").status(), 200);
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
