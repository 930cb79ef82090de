// The server's life: bind, print the address, listen on a thread, wait for
// the stop flag, then stop the render (releasing frame waiters) and the server.
#include "live_view.h"

#include <arpa/inet.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "bvh/scene_bvh4.h"
#include "io/scene_error.h"
#include "routes.h"

namespace pt::live {

bool is_loopback(const std::string& address) {
  if (address == "localhost" || address == "::1") return true;
  in_addr a{};
  return inet_pton(AF_INET, address.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 24) == 127;
}

namespace {

/// "host:port" as a URL and a Host header write it (IPv6 literals in brackets).
std::string host_port(const std::string& host, int port) {
  return (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

}  // namespace

int serve_live_view(const Scene& scene, const LiveOptions& o, const std::atomic<bool>& stop) {
  SceneBvh4 bvh(scene);
  HttpServer server(o.limits, [](const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
  });
  const int port = server.bind(o.bind, o.port);
  if (port < 0)
    throw InputError("--serve: cannot listen on " + host_port(o.bind, o.port) +
                     " (in use, or not an address of this machine)");
  RouteConfig routes{o.directory, o.camera_file, o.image_file, {}, scene.name};
  if (is_loopback(o.bind))
    routes.hosts = {host_port("127.0.0.1", port), host_port("localhost", port), host_port("::1", port),
                    host_port(o.bind, port)};
  RenderSession session(scene, bvh, o.session);
  add_routes(server, session, bvh, routes);
  std::thread listener([&server] { server.listen_after_bind(); });
  if (!o.quiet) {
    const std::string shown = o.bind == "0.0.0.0" || o.bind == "::" ? "127.0.0.1" : o.bind;
    std::printf("Live view of %s at http://%s/ (Ctrl-C stops)\n", scene.name.c_str(), host_port(shown, port).c_str());
    if (!is_loopback(o.bind))
      std::printf("warning: listening on %s: anyone who can reach it can steer the render and write %s and %s\n",
                  o.bind.c_str(), o.camera_file.c_str(), o.image_file.c_str());
    std::fflush(stdout);
  }
  while (!stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  session.stop();
  server.stop();
  listener.join();
  if (!o.quiet) std::printf("Live view stopped\n");
  return 0;
}

}  // namespace pt::live
