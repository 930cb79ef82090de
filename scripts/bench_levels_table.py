#!/usr/bin/env python3
"""Tables of scripts/bench_levels.sh: per level, this BVH4's best method
against Embree's best (restricted to the same instruction set) per ray set and
thread count, and whole CBbunny renders per engine (medians).

    python3 scripts/bench_levels_table.py LEVEL...   (reads out/levels/)
"""
import glob
import json
import statistics
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from bench_table import KINDS, OURS, best, collect  # noqa: E402


def trace_rows(level):
    data = json.load(open(f"out/levels/trace_{level}.json"))
    trace, build, _ = collect(data)
    scenes = list(dict.fromkeys(s for (s, _, _) in trace))
    for scene in scenes:
        cells = []
        for threads in (1, 2):
            for kind in KINDS:
                row = trace.get((scene, kind, threads), {})
                ours, _ = best(row, OURS)
                theirs, _ = best(row, ["embree"])
                cells.append(f"{ours:.1f} / {theirs:.1f} ({ours / theirs:.2f}x)" if ours and theirs else "")
        yield scene, data["context"].get("embree", "absent"), cells


def render_medians(level):
    times = {}
    for path in glob.glob(f"out/levels/render_{level}_*.json"):
        for b in json.load(open(path))["benchmarks"]:
            times.setdefault(b["run_name"].split("/")[2], []).append(b["seconds"])
    return {engine: statistics.median(t) for engine, t in times.items()}


def main(levels):
    print("bench_trace: Mrays/s of this BVH4's best method / Embree's best method (ratio); 1 thread over thread "
          "CPU time, 2 threads over wall time; medians\n")
    print("| level | scene | primary 1T | diffuse 1T | shadow 1T | primary 2T | diffuse 2T | shadow 2T |")
    print("|---|---|---|---|---|---|---|---|")
    embree = {}
    for level in levels:
        for scene, embree[level], cells in trace_rows(level):
            print(f"| {level} | {scene} | " + " | ".join(cells) + " |")
    print("\nEmbree: " + "; ".join(f"{level}: {e}" for level, e in embree.items()))
    print("\nbench_render, CBbunny 480x360 -s 64 -l 4 -m 5, 2 threads, course framing: wall seconds, medians\n")
    print("| level | wavefront | megakernel | reference | wavefront vs megakernel |")
    print("|---|---|---|---|---|")
    for level in levels:
        m = render_medians(level)
        w, k, r = m.get("wavefront"), m.get("megakernel"), m.get("reference")
        print(f"| {level} | {w:.2f} | {k:.2f} | {r:.2f} | {k / w:.2f}x |")


if __name__ == "__main__":
    main(sys.argv[1:])
