#!/usr/bin/env python3
"""Median table of bench_render's JSON: per scene and engine the wall time,
samples and rays per second, and each engine's speed relative to the
megakernel; for the wavefront, how much faster it is with its queues by
material kind than with every shading kernel run over every ray.

    /usr/bin/python3 scripts/bench_render_table.py out/bench_render.json
"""
import json
import statistics
import sys
from collections import defaultdict


def main(path):
    data = json.load(open(path))
    runs = defaultdict(list)  # (scene, engine) -> [entry]
    for e in data["benchmarks"]:
        if e.get("run_type") != "iteration" or e.get("error_occurred"):
            continue
        scene, engine = e["run_name"].split("/")[1:3]
        runs[(scene, engine)].append(e)
    scenes = sorted({s for s, _ in runs})
    engines = ["wavefront", "wavefront_no_packets", "wavefront_unsorted", "megakernel", "reference"]
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


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/bench_render.json")
