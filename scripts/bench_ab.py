#!/usr/bin/env python3
"""A/B of two bench_trace binaries (say, main and a change) on a shared machine.

Runs A and B alternately, `rounds` times each (A first in odd rounds, B first
in even ones), one repetition per run, on the same benchmark filter; then
prints per benchmark the median rate of each (Mrays/s; builds/s for builds) and the median and range of the
paired ratios B/A, and for the BVH4 tracers nodes visited and triangles
tested per ray. Pairs share a round, so load that comes and goes on the
machine hits both sides alike. Writes the raw runs to OUT.json.

    python3 scripts/bench_ab.py A/bench_trace B/bench_trace FILTER [rounds] [OUT]

A and B are commands: a binary, or a binary with its flags in one quoted
argument ('build/bench/bench_trace --collapse-costs=1,0.7,0.6,16'). E.g.
    python3 scripts/bench_ab.py /tmp/main/build/bench/bench_trace build/bench/bench_trace \\
        'trace/CBbunny_x64/(diffuse|shadow)/(bvh4|embree_high_single)/' 5 out/ab
"""
import json
import shlex
import statistics
import subprocess
import sys
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
            continue
        name = e["name"].removesuffix("/manual_time").removesuffix("/real_time")
        if "rays_per_s" in e:
            found[name] = (e["rays_per_s"], e.get("nodes_per_ray"), e.get("triangles_per_ray"))
        elif name.startswith("build/"):
            found[name] = (1000.0 / e["real_time"], e.get("bytes_per_triangle"), None)  # builds per second
    return found


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    a, b, flt = sys.argv[1:4]
    rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 5
    out = sys.argv[5] if len(sys.argv) > 5 else "out/ab"
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


if __name__ == "__main__":
    main()
