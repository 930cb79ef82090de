#!/usr/bin/python3
"""Tables of the benchmarks' Google Benchmark JSON (what scripts/bench.sh writes):

    bench_tables.py summary [out/bench.json]        bench_trace: per scene and ray set, this tracer's best rate,
                                                    Embree's best rate and method, and the ratio (plain text)
    bench_tables.py trace [out/bench.json]          bench_trace: Mrays/s of every tracer per scene, ray set
                                                    and thread count, this BVH4's best / Embree's best, builds
    bench_tables.py render [out/bench_render.json]  bench_render: wall time, samples and rays per second by engine
    bench_tables.py levels LEVEL...                 bench.sh levels: both at every level (reads out/levels/)
    bench_tables.py dispatch LEVEL...               bench.sh dispatch: dispatched / single-level render time
    bench_tables.py rayfiles [DIR]                  bench.sh rayfiles: trace_rays' queue tracer against Embree's
                                                    best method per level, scene and ray file (out/rayfiles/)
summary and trace read Google Benchmark JSON, or a results file that wraps it or holds its
rates (results/README.md).
"""
import glob
import json
import os
import re
import statistics
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ptlib.results import KINDS, load, ours_and_embree, scenes_in_order, trace_rates  # noqa: E402


def collect(data):
    """bench_trace's rates and builds (ptlib.results.trace_rates), with the builds' Google Benchmark fields."""
    trace, builds, errors = trace_rates(data)
    build = defaultdict(dict)
    for scene, entries in builds.items():
        for key, b in entries.items():
            build[scene][key] = {"real_time": b["ms"], "bytes_per_triangle": b.get("bytes_per_triangle") or 0,
                                 "triangles": b.get("triangles")}
    return trace, build, errors


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
            (ours, ours_name), (theirs, theirs_name) = ours_and_embree(row)
            ratio = f"**{ours / theirs:.2f}x** ({ours_name} vs {theirs_name})" if ours and theirs else ""
            lines.append(f"| {kind} | {threads} | " + " | ".join(cells) + f" | {ratio} |")
    return lines


def summary_table(trace, scenes):
    """Per scene and ray set: this BVH4's best method and Embree's best (the fastest of all its methods and
    both builds), 1 and 2 threads."""
    lines = ["| scene | rays | 1 thread: ours / Embree's best | ratio | 2 threads: ours / Embree's best | ratio |",
             "|---|---|---|---|---|---|"]
    for scene in scenes:
        for kind in KINDS:
            cells = []
            for threads in (1, 2):
                row = trace.get((scene, kind, threads), {})
                (ours, ours_name), (theirs, theirs_name) = ours_and_embree(row)
                if ours and theirs:
                    cells += [f"{ours:.1f} ({ours_name}) / {theirs:.1f} ({theirs_name.removeprefix('embree_')})",
                              f"**{ours / theirs:.2f}x**"]
                else:
                    cells += ["", ""]
            if any(cells):
                lines.append(f"| {scene} | {kind} | " + " | ".join(cells) + " |")
    return lines


def triangles_of(builds):
    """The scene's triangle count, as its build benchmarks report it (None without one)."""
    return next((e.get("triangles") for e in builds.values()), None)


def compact_table(trace, build, scenes, threads):
    """One line per scene: per ray set of the benchmark's five, this BVH4's best / Embree's best as a ratio
    (with both rates, Mrays/s), then the build times (1 thread) and sizes."""
    kinds = ["primary", "diffuse", "shadow", "bounce_queues", "shadow_queues"]
    lines = ["| scene (triangles) | " + " | ".join(k.replace("_", " ") for k in kinds) +
             " | build ms: ours / Embree HQ | bytes/triangle: ours / Embree |",
             "|---|" + "---|" * (len(kinds) + 2)]
    for scene in scenes:
        cells = []
        for kind in kinds:
            row = trace.get((scene, kind, threads), {})
            (ours, _), (theirs, _) = ours_and_embree(row)
            cells.append(f"{ours / theirs:.2f}x ({ours:.1f} / {theirs:.1f})" if ours and theirs else "")
        b = build.get(scene, {})
        mine, hq = b.get(("bvh4", 1)), b.get(("embree_high", 1))
        tris = triangles_of(b)
        name = f"{scene} ({int(tris):,})" if tris else scene
        ms = f"{mine['real_time']:.1f} / {hq['real_time']:.1f}" if mine and hq else ""
        size = (f"{mine.get('bytes_per_triangle', 0):.1f} / {hq.get('bytes_per_triangle', 0):.1f}"
                if mine and hq else "")
        if any(cells):
            lines.append(f"| {name} | " + " | ".join(cells) + f" | {ms} | {size} |")
    return lines


def build_table(scene, builds):
    lines = ["| builder | threads | build ms | bytes per triangle | vs embree_high |",
             "|---|---|---|---|---|"]
    for (builder, threads), e in sorted(builds.items()):
        ref = builds.get(("embree_high", threads))
        ratio = f"{e['real_time'] / ref['real_time']:.2f}x" if ref else ""
        lines.append(f"| {builder} | {threads} | {e['real_time']:.1f} | {e.get('bytes_per_triangle', 0):.1f} | {ratio} |")
    return lines


def describe_run(data):
    """The lines that say where a run's figures come from: its results record, or Google Benchmark's context."""
    if "host" in data:
        h = data["host"]
        lines = [f"{data.get('title', '')}", "",
                 f"host: {h.get('cpu', '?')} (family {h.get('cpu_family', '?')}, model {h.get('cpu_model', '?')}), "
                 f"{h.get('cores', '?')} cores; level {data.get('isa') or '-'}; {data.get('date', '?')}; "
                 f"commit {data.get('commit', '?')}", "", f"command: `{data.get('command', '?')}`"]
        if data.get("notes"):
            lines += ["", data["notes"]]
        return lines
    context = data.get("context", {})
    return [f"{context.get('date', '')}; {context.get('num_cpus', '?')} CPUs; Embree: {context.get('embree', 'absent')}; "
            f"{context.get('rays', '')}"]


def summary_text(trace, scenes):
    """The readable summary bench.sh trace leads with: per scene and ray set, this tracer's best rate,
    Embree's best rate with its method, and the ratio, for each thread count."""
    threads = sorted({t for (_, _, t) in trace})
    group = "{:>8} {:>8} {:26} {:>6}"
    head = f"{'':14} {'':16}" + "".join(f" | {f'{t} thread' + ('s' if t > 1 else ''):^51}" for t in threads)
    cols = f"{'scene':14} {'rays':16}" + "".join(" | " + group.format("ours", "Embree", "Embree's method", "ratio")
                                                for _ in threads)
    lines = ["Mrays/s: this tracer's best method, and Embree's best of all its methods and both builds;",
             "1 thread over the thread's CPU time, 2 threads over wall time", "", head, cols, "-" * len(cols)]
    for scene in scenes:
        for kind in KINDS:
            row, found = f"{scene:14} {kind:16}", False
            for t in threads:
                (ours, _), (theirs, name) = ours_and_embree(trace.get((scene, kind, t), {}))
                if ours and theirs:
                    found = True
                    row += " | " + group.format(f"{ours:.1f}", f"{theirs:.1f}", name.removeprefix("embree_"),
                                                f"{ours / theirs:.2f}x")
                else:
                    row += " | " + group.format("", "", "", "")
            if found:
                lines.append(row.rstrip())
    return lines


def summary_main(path="out/bench.json"):
    data = load(path)
    trace, build, errors = collect(data)
    print("\n".join(summary_text(trace, scenes_in_order(trace, build))))
    if errors:
        print(f"not timed: {len(errors)} benchmarks (the full table lists them)")


def trace_main(path="out/bench.json"):
    data = load(path)
    trace, build, errors = collect(data)
    print("# bench_trace: every rate\n")
    print("\n".join(describe_run(data)) + "\n")
    print("Mrays/s, 1 thread over the thread's CPU time, 2 threads over wall time.\n")
    scenes = scenes_in_order(trace, build)
    print("## This BVH4's best method against Embree's best\n")
    print("\n".join(summary_table(trace, scenes)) + "\n")
    for threads in (1, 2):
        print(f"## Ratios per scene, {threads} thread{'s' if threads > 1 else ''} (ours / Embree's best, Mrays/s)\n")
        print("\n".join(compact_table(trace, build, scenes, threads)) + "\n")
    for scene in scenes:
        tris = triangles_of(build.get(scene, {}))
        print(f"## {scene}" + (f" ({int(tris):,} triangles)" if tris else "") + "\n")
        print("\n".join(trace_table(scene, trace)) + "\n")
        if scene in build:
            print("\n".join(build_table(scene, build[scene])) + "\n")
    if errors:
        print("## Not timed\n")
        print("\n".join(f"- {e}" for e in errors))



def benchmark_json(path):
    """Google Benchmark's JSON in `path`, itself or wrapped in a results record."""
    data = load(path)
    return data.get("benchmark", data)


def render_main(path="out/bench_render.json"):
    data = benchmark_json(path)
    runs = defaultdict(list)  # (scene, engine) -> [entry]
    for e in data["benchmarks"]:
        if e.get("run_type") != "iteration" or e.get("error_occurred"):
            continue
        scene, engine = e["run_name"].split("/")[1:3]
        runs[(scene, engine)].append(e)
    scenes = sorted({s for s, _ in runs})
    engines = ["wavefront", "wavefront_single", "wavefront_unsorted", "megakernel", "reference"]
    print(f"machine: {data['context'].get('host_name', '?')}, {data['context'].get('num_cpus', '?')} CPUs; "
          f"medians of {max(len(v) for v in runs.values()) if runs else 0} interleaved runs\n")
    print("| scene | engine | wall s | Msamples/s | Mrays/s | rays (M) | vs megakernel | sorted by material vs unsorted |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        med = {}
        for engine in engines:
            entries = runs.get((scene, engine))
            if not entries:
                continue
            med[engine] = {k: statistics.median(e[k] for e in entries)
                           for k in ("seconds", "samples_per_s", "mrays_per_s", "rays")}
        for engine, m in med.items():
            ratio = med["megakernel"]["seconds"] / m["seconds"] if "megakernel" in med else float("nan")
            sort = ""
            if engine == "wavefront" and "wavefront_unsorted" in med:
                sort = f"{med['wavefront_unsorted']['seconds'] / m['seconds']:.3f}x"
            print(f"| {scene.removesuffix('.dae')} | {engine} | {m['seconds']:.3f} | {m['samples_per_s'] / 1e6:.2f} | "
                  f"{m['mrays_per_s']:.1f} | {m['rays'] / 1e6:.1f} | {ratio:.2f}x | {sort} |")



def trace_rows(level):
    data = load(f"out/levels/trace_{level}.json")
    trace, build, _ = collect(data)
    scenes = list(dict.fromkeys(s for (s, _, _) in trace))
    for scene in scenes:
        cells = []
        for threads in (1, 2):
            for kind in KINDS:
                row = trace.get((scene, kind, threads), {})
                (ours, _), (theirs, _) = ours_and_embree(row)
                cells.append(f"{ours:.1f} / {theirs:.1f} ({ours / theirs:.2f}x)" if ours and theirs else "")
        yield scene, data.get("benchmark", data)["context"].get("embree", "absent"), cells


def render_medians(level):
    times = {}
    for path in glob.glob(f"out/levels/render_{level}_*.json"):
        for b in benchmark_json(path)["benchmarks"]:
            times.setdefault(b["run_name"].split("/")[2], []).append(b["seconds"])
    return {engine: statistics.median(t) for engine, t in times.items()}


def levels_main(*levels):
    print("bench_trace: Mrays/s of this BVH4's best method / Embree's best method (ratio); 1 thread over thread "
          "CPU time, 2 threads over wall time; medians\n")
    print("| level | scene | " + " | ".join(f"{k} {t}T" for t in (1, 2) for k in KINDS) + " |")
    print("|---|---|" + "---|" * (2 * len(KINDS)))
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



def dispatch_main(*levels):
    print("| level | engine | dispatched s | single-level s | dispatched / single |")
    print("|---|---|---|---|---|")
    for level in levels:
        times = {}
        for kind in ("dispatched", "single"):
            for path in glob.glob(f"out/dispatch/{kind}_{level}_*.json"):
                for b in benchmark_json(path)["benchmarks"]:
                    engine = b["run_name"].split("/")[2]
                    times.setdefault((kind, engine), []).append(b["seconds"])
        for engine in ("wavefront", "megakernel"):
            d = statistics.median(times[("dispatched", engine)])
            s = statistics.median(times[("single", engine)])
            print(f"| {level} | {engine} | {d:.3f} | {s:.3f} | {d / s:.3f} |")


RAYFILE = re.compile(r"^(?P<level>[^_]+)_(?P<scene>.+)_(?P<set>primary|diffuse|shadow)_(?P<round>\d+)\.jsonl$")


def rayfiles_runs(directory="out/rayfiles"):
    """Every line trace_rays wrote in bench.sh rayfiles' files, with the file's level, scene, set and round."""
    runs = []
    for path in sorted(glob.glob(f"{directory}/*.jsonl")):
        m = RAYFILE.match(os.path.basename(path))
        if not m:
            continue
        for line in open(path):
            if line.startswith("{"):
                runs.append(dict(json.loads(line), level=m["level"], scene=m["scene"], set=m["set"],
                                 round=int(m["round"])))
    return runs


def rayfiles_table(runs):
    """Medians over the rounds of each method's 1-thread rate; the ratio is
    the queue tracer's median over Embree's best median."""
    rates = defaultdict(lambda: defaultdict(list))  # (level, scene, set) -> method -> Mrays/s per round
    for d in runs:
        if d["threads"] == 1:
            rates[(d["level"], d["scene"], d["set"])][d["method"]].append(d["mrays_per_s"])
    lines = ["| level | scene | rays | queue tracer Mrays/s | Embree's best Mrays/s (method) | ratio | rounds |",
             "|---|---|---|---|---|---|---|"]
    order = {"primary": 0, "diffuse": 1, "shadow": 2}
    for (level, scene, kind), methods in sorted(rates.items(), key=lambda i: (i[0][0], i[0][1], order[i[0][2]])):
        if "queue" not in methods:
            continue
        ours = statistics.median(methods["queue"])
        embree = {k: statistics.median(v) for k, v in methods.items() if k.startswith("embree")}
        if not embree:
            continue
        top = max(embree, key=embree.get)
        lines.append(f"| {level} | {scene} | {kind} | {ours:.1f} | {embree[top]:.1f} ({top.removeprefix('embree_')}) "
                     f"| {ours / embree[top]:.2f} | {len(methods['queue'])} |")
    return lines


def rayfiles_main(directory="out/rayfiles"):
    print("\n".join(rayfiles_table(rayfiles_runs(directory))))


COMMANDS = {"summary": summary_main, "trace": trace_main, "render": render_main, "levels": levels_main, "dispatch": dispatch_main,
            "rayfiles": rayfiles_main}

if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in COMMANDS:
        sys.exit(__doc__)
    COMMANDS[sys.argv[1]](*sys.argv[2:])
