// The server's life: bind, print the address, serve (libmicrohttpd's
// threads), wait for the stop flag, then stop the server and the render.
#include "live_view.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
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

/// The addresses of this machine's interfaces, as a Host header writes them (IPv6 in brackets, no scope).
std::vector<std::string> interface_addresses() {
  std::vector<std::string> out;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return out;
  for (ifaddrs* a = list; a; a = a->ifa_next) {
    if (!a->ifa_addr) continue;
    char text[INET6_ADDRSTRLEN] = "";
    if (a->ifa_addr->sa_family == AF_INET) {
      inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof text);
    } else if (a->ifa_addr->sa_family == AF_INET6) {
      inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(a->ifa_addr)->sin6_addr, text, sizeof text);
    }
    if (text[0]) out.push_back(text);
  }
  freeifaddrs(list);
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::vector<std::string> accepted_hosts(const std::string& bind, int port) {
  std::vector<std::string> names = {"127.0.0.1", "localhost", "::1", bind};
  if (!is_loopback(bind)) {
    char name[256] = "";
    if (gethostname(name, sizeof name - 1) == 0 && name[0]) names.push_back(name);
    if (bind == "0.0.0.0" || bind == "::")
      for (const std::string& a : interface_addresses()) names.push_back(a);
  }
  std::vector<std::string> hosts;
  for (const std::string& n : names) {
    if (n == "0.0.0.0" || n == "::") continue;  // not an address a client connects to
    hosts.push_back(lower(host_port(n, port)));
    if (port == 80) hosts.push_back(lower(n.find(':') != std::string::npos ? "[" + n + "]" : n));
  }
  std::sort(hosts.begin(), hosts.end());
  hosts.erase(std::unique(hosts.begin(), hosts.end()), hosts.end());
  return hosts;
}

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
  RouteConfig routes{o.directory, o.camera_file, o.image_file, accepted_hosts(o.bind, port), scene.name};
  SessionConfig session_config = o.session;
  session_config.log = [&server](const std::string& line) { server.log(line); };
  session_config.frames_changed = [&server] { server.wake(); };
  RenderSession session(scene, bvh, session_config);
  add_routes(server, session, bvh, routes);
  if (!server.start()) throw InputError("--serve: the HTTP server (libmicrohttpd) did not start");
  if (!o.quiet) {
    const std::string shown = o.bind == "0.0.0.0" || o.bind == "::" ? "127.0.0.1" : o.bind;
    std::printf("Live view of %s at http://%s/ (Ctrl-C stops)\n", scene.name.c_str(), host_port(shown, port).c_str());
    if (!is_loopback(o.bind))
      std::printf("warning: listening on %s: anyone who can reach it can steer the render and write %s and %s\n",
                  o.bind.c_str(), o.camera_file.c_str(), o.image_file.c_str());
    std::fflush(stdout);
  }
  while (!stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  server.stop();   // waiting frame requests get 503, then every connection closes
  session.stop();  // the render ends within a wave
  if (!o.quiet) std::printf("Live view stopped\n");
  return 0;
}

}  // namespace pt::live
