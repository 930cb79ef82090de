#!/usr/bin/env python3
"""Short tables from bench_trace's JSON (Google Benchmark --benchmark_out).

Per scene: throughput in million rays per second of every tracer per ray set
and thread count (medians when the run had repetitions), the ratio of this
BVH4's best method to Embree's best method, and build time and memory.

    python3 scripts/bench_table.py out/bench.json
"""
import json
import re
import sys
from collections import defaultdict

TRACE = re.compile(r"^trace/(?P<scene>[^/]+)/(?P<kind>[^/]+)/(?P<tracer>[^/]+)/threads:(?P<threads>\d+)$")
BUILD = re.compile(r"^build/(?P<scene>[^/]+)/(?P<builder>[^/]+)/threads:(?P<threads>\d+)$")
KINDS = ["primary", "diffuse", "shadow"]
OURS = ["bvh4", "bvh4_packet", "bvh4_incoherent"]


def runs(data):
    """Yields (base name, entry): medians when there are aggregates, else single runs."""
    entries = data["benchmarks"]
    has_median = any(e.get("aggregate_name") == "median" for e in entries)
    for e in entries:
        if e.get("error_occurred"):
            continue
        if has_median and e.get("aggregate_name") != "median":
            continue
        name = e.get("run_name", e["name"]).removesuffix("/manual_time").removesuffix("/real_time")
        yield name, e


def collect(data):
    trace = defaultdict(dict)  # (scene, kind, threads) -> tracer -> Mrays/s
    build = defaultdict(dict)  # scene -> (builder, threads) -> entry
    errors = [e["name"] + ": " + e.get("error_message", "") for e in data["benchmarks"] if e.get("error_occurred")]
    for name, e in runs(data):
        if m := TRACE.match(name):
            key = (m["scene"], m["kind"], int(m["threads"]))
            trace[key][m["tracer"]] = e["rays_per_s"] / 1e6
        elif m := BUILD.match(name):
            build[m["scene"]][(m["builder"], int(m["threads"]))] = e
    return trace, build, errors


def best(row, prefix_list):
    found = [(v, k) for k, v in row.items() if any(k == p or k.startswith(p) for p in prefix_list)]
    return max(found) if found else (None, None)


def trace_table(scene, trace):
    tracers = sorted({t for (s, _, _), row in trace.items() if s == scene for t in row})
    lines = ["| rays | threads | " + " | ".join(tracers) + " | bvh4 best / Embree best |",
             "|---|---|" + "---|" * len(tracers) + "---|"]
    for kind in KINDS:
        for threads in (1, 2):
            row = trace.get((scene, kind, threads))
            if not row:
                continue
            cells = [f"{row[t]:.2f}" if t in row else "" for t in tracers]
            ours, ours_name = best(row, OURS)
            theirs, theirs_name = best(row, ["embree"])
            ratio = f"**{ours / theirs:.2f}x** ({ours_name} vs {theirs_name})" if ours and theirs else ""
            lines.append(f"| {kind} | {threads} | " + " | ".join(cells) + f" | {ratio} |")
    return lines


def build_table(scene, builds):
    lines = ["| builder | threads | build ms | bytes per triangle | vs embree_high |",
             "|---|---|---|---|---|"]
    for (builder, threads), e in sorted(builds.items()):
        ref = builds.get(("embree_high", threads))
        ratio = f"{e['real_time'] / ref['real_time']:.2f}x" if ref else ""
        lines.append(f"| {builder} | {threads} | {e['real_time']:.1f} | {e.get('bytes_per_triangle', 0):.1f} | {ratio} |")
    return lines


def main(path):
    with open(path) as f:
        data = json.load(f)
    trace, build, errors = collect(data)
    context = data.get("context", {})
    print(f"# bench_trace, {context.get('date', '')}")
    print(f"host: {context.get('num_cpus', '?')} CPUs; Embree: {context.get('embree', 'absent')}; "
          f"{context.get('rays', '')}; Mrays/s, 1 thread over thread CPU time, 2 threads over wall time\n")
    scenes = list(dict.fromkeys([s for (s, _, _) in trace] + list(build)))
    for scene in scenes:
        tris = next((e.get("triangles") for e in build.get(scene, {}).values()), None)
        print(f"## {scene}" + (f" ({int(tris):,} triangles)" if tris else "") + "\n")
        print("\n".join(trace_table(scene, trace)) + "\n")
        if scene in build:
            print("\n".join(build_table(scene, build[scene])) + "\n")
    if errors:
        print("## Not timed\n")
        print("\n".join(f"- {e}" for e in errors))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/bench.json")
