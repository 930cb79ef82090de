#!/usr/bin/env python3
"""Paired A/B runs on a shared, noisy machine: the variants run alternately
(the order reversed every other round), so load that comes and goes hits all
of them alike, and the medians of the paired ratios are the figures to quote.

  ab.py renders ROUNDS SCENES LABEL=COMMAND [LABEL=COMMAND ...]
      Whole renders: each COMMAND is a pathtracer command line without scene
      and output; SCENES a comma-separated list of shared CS184 scene names.
      Prints each variant's median render time (the end report's) and its
      paired ratio to the first variant. E.g. two builds:
        F="-t 2 -s 64 -l 4 -m 5 -a 64 0 -r 480 360"
        python3 scripts/ab.py renders 5 CBbunny,CBcoil,CBspheres_lambertian \
            "main=/tmp/main/build/cli/pathtracer $F" "new=build/cli/pathtracer $F"
      or a setting (the sampler's cost):
        B=build/cli/pathtracer; F="-t 2 -s 64 -l 1 -m 5 -a 64 0 -r 480 360"
        python3 scripts/ab.py renders 9 CBbunny,CBspheres_lambertian \
            "independent=$B $F --sampler independent" "sobol=$B $F"

  ab.py bench A B FILTER [ROUNDS] [OUT]
      Two bench_trace commands (a binary, or a binary with its flags in one
      quoted argument) on the same benchmark filter, one repetition per run:
      per benchmark both medians (Mrays/s; builds/s for builds), the median
      and range of the paired ratios B/A, and nodes visited and triangles
      tested per ray; the raw runs in OUT.json. E.g.
        python3 scripts/ab.py bench /tmp/main/build/bench/bench_trace build/bench/bench_trace \
            'trace/CBbunny_x64/(diffuse|shadow)/(bvh4|embree_high_single)/' 5 out/ab
"""
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
from collections import defaultdict

def run(command, flt, out):
    cmd = shlex.split(command) + [f"--benchmark_filter={flt}", "--benchmark_min_time=0.3",
           f"--benchmark_out={out}", "--benchmark_out_format=json"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        return json.load(f)["benchmarks"]


def rates(entries):
    found = {}
    for e in entries:
        if e.get("error_occurred"):
            print(f"ab.py: {e['name']}: {e.get('error_message', 'error')}", file=sys.stderr)
            continue
        name = e["name"].removesuffix("/manual_time").removesuffix("/real_time")
        if "rays_per_s" in e:
            found[name] = (e["rays_per_s"], e.get("nodes_per_ray"), e.get("triangles_per_ray"))
        elif name.startswith("build/"):
            found[name] = (1000.0 / e["real_time"], e.get("bytes_per_triangle"), None)  # builds per second
    return found


def bench_main(args):
    if len(args) < 3:
        sys.exit(__doc__)
    a, b, flt = args[:3]
    rounds = int(args[3]) if len(args) > 3 else 5
    out = args[4] if len(args) > 4 else "out/ab"
    samples = defaultdict(lambda: ([], []))
    raw = []
    for r in range(rounds):
        order = [(0, a), (1, b)] if r % 2 == 0 else [(1, b), (0, a)]
        for side, binary in order:
            entries = run(binary, flt, f"{out}.{side}.json")
            raw.append({"round": r, "side": "AB"[side], "benchmarks": entries})
            for name, value in rates(entries).items():
                samples[name][side].append(value)
    with open(f"{out}.json", "w") as f:
        json.dump(raw, f)
    if not any(sa and sb for sa, sb in samples.values()):
        sys.exit(f"ab.py: no benchmark matching {flt!r} ran in both builds (raw runs: {out}.json)")
    print(f"{'benchmark':64} {'A':>9} {'B':>9} {'B/A':>6} {'range':>13}  nodes A/B   tris A/B")
    for name in sorted(samples):
        sa, sb = samples[name]
        n = min(len(sa), len(sb))
        if n == 0:
            continue
        ratios = [sb[i][0] / sa[i][0] for i in range(n)]
        scale = 1.0 if name.startswith("build/") else 1e6  # builds/s, else Mrays/s
        ma = statistics.median(x[0] for x in sa) / scale
        mb = statistics.median(x[0] for x in sb) / scale
        work = ""
        if sa[0][1] is not None and sb[0][1] is not None:
            work = f"  {sa[0][1]:.2f}/{sb[0][1]:.2f}"
            if sa[0][2] is not None:
                work += f"  {sa[0][2]:.2f}/{sb[0][2]:.2f}"
        unit = "" if not name.startswith("build/") else " (builds/s; B/tri)"
        print(f"{name + unit:64} {ma:9.3f} {mb:9.3f} {statistics.median(ratios):6.3f}"
              f" {min(ratios):6.3f}-{max(ratios):.3f}{work}")



SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "scenes", "cs184")


def render_seconds(command, scene, output):
    out = subprocess.run(shlex.split(command) + ["-f", output, os.path.join(SCENES, scene + ".dae")],
                         capture_output=True, text=True, stdin=subprocess.DEVNULL, check=True).stdout
    return float(re.search(r"Rendered in ([0-9.]+)", out).group(1))


def renders_main(args):
    if len(args) < 3:
        sys.exit(__doc__)
    rounds, scenes = int(args[0]), args[1].split(",")
    variants = [a.split("=", 1) for a in args[2:]]
    times = {}
    with tempfile.TemporaryDirectory() as tmp:
        output = os.path.join(tmp, "image.png")
        for r in range(rounds):
            order = variants if r % 2 == 0 else variants[::-1]
            for scene in scenes:
                for label, command in order:
                    t = render_seconds(command, scene, output)
                    times.setdefault((scene, label), []).append(t)
                    print(f"run: round {r + 1} {scene} {label} {t:.3f} s", flush=True)
    base = variants[0][0]
    print(f"{'scene':28} {'variant':16} {'median s':>9} {'ratio to ' + base:>18} {'range':>13}")
    for scene in scenes:
        for label, _ in variants:
            ratios = [t / b for t, b in zip(times[(scene, label)], times[(scene, base)])]
            print(f"{scene:28} {label:16} {statistics.median(times[(scene, label)]):9.3f} "
                  f"{statistics.median(ratios):18.3f} {min(ratios):6.3f}-{max(ratios):.3f}")



if __name__ == "__main__":
    modes = {"bench": bench_main, "renders": renders_main}
    if len(sys.argv) < 2 or sys.argv[1] not in modes:
        sys.exit(__doc__)
    modes[sys.argv[1]](sys.argv[2:])
