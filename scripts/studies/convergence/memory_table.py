#!/usr/bin/python3
"""Memory per shared scene: runs `pathtracer --memory` on every public CS184
scene at 480x360 and prints a markdown table of bytes per triangle (scene
arrays, BVH: allocated / in use), the wavefront's queues per thread, bytes
per pixel of everything held per pixel, the total held, and the peak
resident set size of each engine as the kernel accounts it (wait4).

Usage: /usr/bin/python3 scripts/studies/convergence/memory_table.py [PATHTRACER] [SCENE_DIR]"""

import os
import re
import subprocess
import sys
import tempfile

SCENES = ["CBspheres_lambertian", "CBempty", "CBgems", "CBcoil", "CBbunny", "bunny", "cow", "beetle", "teapot",
          "banana"]
ENGINES = ["wavefront", "megakernel", "reference"]
LINE = re.compile(r"^(.*?)\s{2,}(\d+)\s+(\d+)\s+(.*)$")


def run(pathtracer, scene, engine):
    """(lines {structure: (allocated, used)}, header figures, peak RSS bytes) of one render."""
    with tempfile.TemporaryDirectory() as tmp:
        args = [pathtracer, "--engine", engine, "-t", "2", "-s", "1", "-m", "5", "-a", "16", "0", "-r", "480", "360",
                "--memory", "-q", "-f", os.path.join(tmp, "out.png"), scene]
        proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        out = proc.stdout.read()
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit(f"memory_table: {' '.join(args)} failed")
    lines = {}
    for text in out.splitlines():
        m = LINE.match(text)
        if m:
            lines[m.group(1).replace(" [transient]", "")] = (int(m.group(2)), int(m.group(3)))
    total = int(re.search(r"total held \(without transient lines\)\s+(\d+)", out).group(1))
    triangles = int(re.search(r"; (\d+) triangles", out).group(1))
    return lines, total, triangles, usage.ru_maxrss * 1024


def row(pathtracer, scene_dir, name):
    scene = os.path.join(scene_dir, name + ".dae")
    results = {e: run(pathtracer, scene, e) for e in ENGINES}
    lines, total, triangles, _ = results["wavefront"]
    tri = max(triangles, 1)
    scene_alloc = sum(v[0] for k, v in lines.items() if k.startswith("scene:"))
    scene_used = sum(v[1] for k, v in lines.items() if k.startswith("scene:"))
    bvh_alloc, bvh_used = next(v for k, v in lines.items() if k.endswith(": nodes and leaves"))
    per_pixel = sum(v[0] for k, v in lines.items()
                    if k.startswith(("pass driver:", "film:"))) / (480 * 360)
    queues = lines["wavefront: wave queues"][0] / 2 / 1024
    rss = " / ".join(f"{results[e][3] / 1e6:.1f}" for e in ENGINES)
    return (f"| {name} | {triangles} | {scene_alloc / tri:.1f} / {scene_used / tri:.1f} | "
            f"{bvh_alloc / tri:.1f} / {bvh_used / tri:.1f} | {queues:.0f} | {per_pixel:.0f} | "
            f"{total / 1e6:.1f} | {rss} |")


def main():
    pathtracer = sys.argv[1] if len(sys.argv) > 1 else "build/cli/pathtracer"
    scene_dir = sys.argv[2] if len(sys.argv) > 2 else "../shared/scenes/cs184"
    print("Memory at 480x360, `-t 2 -s 1 -m 5` (`pathtracer --memory`; B = bytes, MB = 10^6 bytes). "
          "Scene and BVH columns: bytes per triangle allocated / in use. Per pixel: accumulators, pixel lists and "
          "film of the pass-based engines. Held: every structure alive at the end of the wavefront render. "
          "Peak RSS: whole process, wavefront / megakernel / reference engine.\n")
    print("| scene | triangles | scene arrays B/tri | BVH4 B/tri | wave queues KiB/thread | per pixel B | "
          "held MB | peak RSS MB |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name in SCENES:
        print(row(pathtracer, scene_dir, name))


if __name__ == "__main__":
    main()
