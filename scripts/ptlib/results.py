"""Results files (results/README.md): one measurement each, as JSON with

  kind     what it holds: "bench_trace" (Google Benchmark JSON, or its rates as cells),
           "table" (a table of figures as measured), ...
  title    one line saying what was measured
  host     the machine (ptlib.host.describe: cpu, cpu_family, cpu_model, cores, levels)
  isa      the instruction-set level the run used ("" when the file spans levels)
  date     the day of the run (YYYY-MM-DD)
  commit   the commit the binaries were built from
  command  the command that made it
  notes    anything a reader needs to weigh the figures (optional)

and the payload: "benchmark" (bench_trace's own JSON), or "cells" and "builds"
(bench_trace's rates, converted from an older table), or "columns" and "rows".
"""
import datetime
import json
import os
import re

from . import host

TRACE = re.compile(r"^trace/(?P<scene>[^/]+)/(?P<kind>[^/]+)/(?P<tracer>[^/]+)/threads:(?P<threads>\d+)$")
BUILD = re.compile(r"^build/(?P<scene>[^/]+)/(?P<builder>[^/]+)/threads:(?P<threads>\d+)$")
KINDS = ["primary", "diffuse", "shadow", "diffuse_shuffled", "shadow_shuffled", "bounce_queues", "shadow_queues"]
OURS = ["bvh4", "bvh4_queue", "bvh4_packet", "bvh4_incoherent"]  # this tracer's methods; bvh4_watertight is a variant


def new(kind, title, command, isa, notes="", **payload):
    """A results record of this machine and checkout, today."""
    rec = {"kind": kind, "title": title, "host": host.describe(), "isa": isa,
           "date": datetime.date.today().isoformat(), "commit": host.commit(), "command": command}
    if notes:
        rec["notes"] = notes
    rec.update(payload)
    return rec


ONE_LINE_ITEMS = ("cells", "builds", "runs", "rows")  # lists written one item per line


def dumps(rec):
    """JSON of a record: readable fields, and the long lists of data one item per line."""
    def encode(value, indent):
        pad = " " * indent
        if isinstance(value, dict):
            if not value:
                return "{}"
            items = [f"{pad} {json.dumps(str(k))}: " + (
                "[\n" + ",\n".join(f"{pad}  " + json.dumps(x) for x in v) + f"\n{pad} ]"
                if k in ONE_LINE_ITEMS and isinstance(v, list) and v else encode(v, indent + 1))
                for k, v in value.items()]
            return "{\n" + ",\n".join(items) + f"\n{pad}}}"
        if isinstance(value, list) and any(isinstance(x, (dict, list)) for x in value):
            return "[\n" + ",\n".join(f"{pad} " + encode(x, indent + 1) for x in value) + f"\n{pad}]"
        return json.dumps(value)
    return encode(rec, 0) + "\n"


def save(path, rec):
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(dumps(rec))
    os.replace(tmp, path)


def load(path):
    with open(path) as f:
        return json.load(f)


def _benchmark_entries(data):
    """Google Benchmark entries: medians where there are aggregates, else every run, errors left out."""
    entries = data["benchmarks"]
    has_median = any(e.get("aggregate_name") == "median" for e in entries)
    for e in entries:
        if e.get("error_occurred") or (has_median and e.get("aggregate_name") != "median"):
            continue
        yield e.get("run_name", e["name"]).removesuffix("/manual_time").removesuffix("/real_time"), e


def trace_rates(data):
    """bench_trace's rates and builds from Google Benchmark JSON, a results file that wraps it, or one
    with converted cells: ({(scene, rays, threads): {method: Mrays/s}},
    {scene: {(builder, threads): {"ms", "bytes_per_triangle", "triangles"}}}, [errors])."""
    trace, builds, errors = {}, {}, []
    if "cells" in data:
        for c in data["cells"]:
            trace.setdefault((c["scene"], c["rays"], int(c["threads"])), {})[c["method"]] = c["mrays_per_s"]
        for b in data.get("builds", []):
            builds.setdefault(b["scene"], {})[(b["builder"], int(b["threads"]))] = b
        return trace, builds, errors
    bench = data.get("benchmark", data)
    errors = [e["name"] + ": " + e.get("error_message", "") for e in bench["benchmarks"] if e.get("error_occurred")]
    for name, e in _benchmark_entries(bench):
        if m := TRACE.match(name):
            trace.setdefault((m["scene"], m["kind"], int(m["threads"])), {})[m["tracer"]] = e["rays_per_s"] / 1e6
        elif m := BUILD.match(name):
            builds.setdefault(m["scene"], {})[(m["builder"], int(m["threads"]))] = {
                "ms": e["real_time"], "bytes_per_triangle": e.get("bytes_per_triangle"), "triangles": e.get("triangles")}
    return trace, builds, errors


def best(row, names=None, prefix=None):
    """(Mrays/s, method) of the fastest method in `row` among `names`, or among those starting with `prefix`;
    (None, None) when there is none."""
    found = [(v, k) for k, v in row.items() if (names is not None and k in names) or (prefix and k.startswith(prefix))]
    return max(found) if found else (None, None)


def ours_and_embree(row):
    """((Mrays/s, method) of this tracer's best method (OURS), (Mrays/s, method) of Embree's best) for one cell."""
    return best(row, names=OURS), best(row, prefix="embree_")


def scenes_in_order(trace, builds):
    """The scenes of a run, smallest first where the builds give their triangle counts."""
    scenes = list(dict.fromkeys([s for (s, _, _) in trace] + list(builds)))

    def triangles(scene):
        counts = [b.get("triangles") for b in builds.get(scene, {}).values() if b.get("triangles")]
        return counts[0] if counts else float("inf")

    return sorted(scenes, key=triangles)
