#!/usr/bin/python3
"""Measures the live view against its targets and prints medians:

  frames/s while the camera moves  the page in headless Chromium, the camera
                                   orbited to and fro about the scene's camera
                                   by pointer events every animation frame:
                                   new views drawn per second; and an HTTP
                                   client alone (move, then wait for the moved
                                   view's frame, repeated)
  first frame                      ms from the start of a page load to its
                                   first frame drawn (fresh tabs)
  time to 64 samples               from a camera move to the still view's
                                   64-sample frame, against the command line's
                                   `-s 64` render time (interleaved runs); the
                                   view then equals that render bit for bit
                                   (tests/live, tests/browser check it)
  cancellation                     the time from a camera move to the end of
                                   the long pass it cancels

  /usr/bin/python3 scripts/live_bench.py [--scene S] [--flags "-r 320 240 -m 5"] [--runs 7] [--no-browser]
"""
import argparse
import json
import os
import re
import signal
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class Live:
    def __init__(self, binary, flags, scene):
        self.workdir = tempfile.mkdtemp(prefix="pt-live-bench-")
        self.process = subprocess.Popen([binary, "--serve", "0"] + flags + [scene], cwd=self.workdir,
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = ""
        while "http://" not in line:
            line = self.process.stdout.readline()
            if not line:
                sys.exit("the server did not start: " + self.process.stderr.read())
        self.url = re.search(r"(http://[^/]+)/", line).group(1)
        self.cameras_saved = 0  # a named file is never replaced: each camera gets a name of its own

    def open(self, path, method="GET"):
        # Every API request carries the page's header (the server refuses one without it).
        return urllib.request.urlopen(urllib.request.Request(self.url + path, method=method,
                                                             headers={"X-PT-Live": "1"}))

    def post(self, path):
        return json.load(self.open(path, "POST"))

    def get(self, path):
        return json.load(self.open(path))

    def frame(self, after):
        while True:
            reply = self.open("/api/frame?after=%d" % after)
            if reply.status == 200:
                data = reply.read()
                n = struct.unpack("<I", data[:4])[0]
                return json.loads(data[4:4 + n])

    def stop(self):
        self.process.send_signal(signal.SIGINT)
        self.process.communicate(timeout=30)


def median(values):
    return statistics.median(values) if values else float("nan")


def http_frames_per_second(live, seconds):
    """Drag (moves that more moves follow) to and fro about the scene's camera, waiting for each move's
    frame: moved views per second."""
    live.post("/api/nav?op=reset")
    after = live.frame(0)["id"]
    start = time.time()
    views = 0
    while time.time() - start < seconds:
        dx = 3 if views % 40 < 20 else -3
        version = live.post("/api/nav?op=orbit&dx=%d&dy=0&moving=1" % dx)["version"]
        while True:
            f = live.frame(after)
            after = f["id"]
            if f["version"] >= version:
                break
        views += 1
    rate = views / (time.time() - start)
    live.post("/api/nav?op=still")
    return rate, f["width"]


def time_to_samples(live, samples):
    """From a camera move (the scene's camera turned by 7 pixels) to the frame of `samples` samples:
    (wall seconds at the client, the server's seconds since the change, the camera file of the view)."""
    live.post("/api/nav?op=reset")
    after = live.frame(0)["id"]
    t0 = time.time()
    version = live.post("/api/nav?op=orbit&dx=7&dy=1")["version"]
    while True:
        f = live.frame(after)
        after = f["id"]
        if f["version"] == version and f["samples"] >= samples:
            wall = time.time() - t0
            live.cameras_saved += 1
            name = "bench_camera_%d.txt" % live.cameras_saved
            return wall, f["seconds"], live.post("/api/camera/save?name=" + name)["file"]


def cli_seconds(binary, flags, scene, samples, camera):
    """The command line's render time (after loading and the BVH build) of the same view."""
    out = subprocess.run([binary, "-t", str(os.cpu_count()), "-s", str(samples), "-c", camera] + flags +
                         ["-f", os.path.join(tempfile.gettempdir(), "pt_live_bench_cli.png"), scene],
                         capture_output=True, text=True, cwd=tempfile.gettempdir()).stdout
    return float(re.search(r"Rendered in ([0-9.]+) s", out).group(1))


def browser_figures(url, seconds, loads):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    for flag in ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--window-size=1280,800", "--user-data-dir=" + tempfile.mkdtemp()]:
        options.add_argument(flag)
    options.binary_location = "/usr/bin/chromium"
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    try:
        first = []
        for _ in range(loads):
            driver.switch_to.new_window("tab")
            driver.get(url + "/")
            deadline = time.time() + 10
            while not driver.execute_script("return window.ptLive && ptLive.firstFrameMs") and time.time() < deadline:
                time.sleep(0.02)
            first.append(driver.execute_script("return ptLive.firstFrameMs"))
        driver.execute_script("document.getElementById('overlay').scrollIntoView()")
        urllib.request.urlopen(urllib.request.Request(url + "/api/nav?op=reset", method="POST",
                                                      headers={"X-PT-Live": "1"}))
        # Orbit with pointer events once per animation frame (as a mouse drag sends them) for `seconds`.
        result = driver.execute_async_script("""
            const [seconds, done] = arguments;
            const overlay = document.getElementById('overlay');
            const r = overlay.getBoundingClientRect();
            let x = r.left + r.width / 2, y = r.top + r.height / 2;
            const fire = (type) => overlay.dispatchEvent(new PointerEvent(type,
                {clientX: x, clientY: y, pointerId: 1, button: 0, buttons: 1, bubbles: true}));
            fire('pointerdown');
            const start = performance.now();
            const drawn0 = ptLive.framesDrawn;
            let views = new Set(), last = null, moves = 0;
            function step() {  // to and fro: 40 px each way, about the scene's camera
              x += moves % 40 < 20 ? 2 : -2; moves += 1;
              fire('pointermove');
              const f = ptLive.frame;
              if (f !== last) { views.add(f.version); last = f; }
              if (performance.now() - start < seconds * 1000) requestAnimationFrame(step);
              else { fire('pointerup'); done([performance.now() - start, ptLive.framesDrawn - drawn0, views.size, moves,
                                              ptLive.frame.width, ptLive.frame.view_width]); }
            }
            requestAnimationFrame(step);""", seconds)
        return first, result
    finally:
        driver.quit()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pathtracer", default=os.path.join(ROOT, "build/cli/pathtracer"))
    parser.add_argument("--scene", default=os.path.join(ROOT, "../shared/scenes/cs184/CBbunny.dae"))
    parser.add_argument("--flags", default="-r 320 240 -m 5")
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--no-browser", action="store_true")
    args = parser.parse_args()
    flags = args.flags.split()
    print("scene %s, flags %s, %d cores" % (os.path.basename(args.scene), args.flags, os.cpu_count()))

    live = Live(args.pathtracer, flags + ["-s", "64", "-t", str(os.cpu_count())], args.scene)
    state = live.get("/api/state")
    print("live view: %s, %d threads" % (state["isa"], state["threads"]))
    try:
        for preview in ("0", "1"):
            live.post("/api/settings?preview=" + preview)
            runs = [http_frames_per_second(live, 3.0) for _ in range(args.runs)]
            fps = [r[0] for r in runs]
            print("HTTP client dragging, each move waiting for its frame, preview %s (%d px wide): median %.1f moved "
                  "views/s (runs: %s)" % ("automatic" if preview == "0" else "full resolution", runs[-1][1], median(fps),
                                          " ".join("%.1f" % f for f in fps)))
        live.post("/api/settings?preview=0")
        live_wall, live_server, cli = [], [], []
        for _ in range(args.runs):  # interleaved: the machine's load hits both alike
            wall, server, camera = time_to_samples(live, 64)
            live_wall.append(wall)
            live_server.append(server)
            cli.append(cli_seconds(args.pathtracer, flags, args.scene, 64, camera))
        ratios = [a / b for a, b in zip(live_wall, cli)]
        print("time to 64 samples after a move: live %.3f s at the client (server %.3f s); command line -s 64: %.3f s;"
              " live / command line: %.3f (median of the %d interleaved pairs; range %.3f-%.3f) (runs: live %s;"
              " command line %s)" % (
                  median(live_wall), median(live_server), median(cli), median(ratios), len(ratios), min(ratios),
                  max(ratios), " ".join("%.3f" % v for v in live_wall), " ".join("%.3f" % v for v in cli)))
        # Cancellation: move during a long pass (4096 samples, steps up to 0.25 s).
        live.post("/api/settings?samples=4096")
        lat = []
        for _ in range(args.runs):
            time_to_samples(live, 64)
            time.sleep(0.1)
            live.post("/api/nav?op=orbit&dx=1&dy=0")
            time.sleep(0.3)
            lat.append(live.get("/api/state")["counters"]["last_cancel_seconds"])
        counters = live.get("/api/state")["counters"]
        print("cancellation: median %.1f ms from a move to the end of the pass it stops (runs: %s); "
              "at most %d chunks finished after a cancel" % (
                  1e3 * median(lat), " ".join("%.1f" % (1e3 * v) for v in lat), counters["max_chunks_after_cancel"]))
        live.post("/api/settings?samples=64")
        if not args.no_browser:
            live.post("/api/settings?preview=1")  # full resolution while moving: the target's condition
            first, (ms, drawn, views, moves, width, view_width) = browser_figures(live.url, 5.0, args.runs)
            print("first frame after a page load: median %.0f ms (loads: %s)" % (
                median(first), " ".join("%.0f" % v for v in first)))
            print("page, orbiting with a pointer event per animation frame for %.1f s: %.1f frames drawn/s, "
                  "%.1f distinct views/s (%d pointer moves; last frame %d px wide of %d)" % (
                      ms / 1e3, drawn * 1e3 / ms, views * 1e3 / ms, moves, width, view_width))
    finally:
        live.stop()


if __name__ == "__main__":
    main()
