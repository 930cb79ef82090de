#!/usr/bin/python3
"""Paired A/B runs on a shared, noisy machine: the variants run alternately
(the order reversed every other round, ptlib.paired), so load that comes and
goes hits all of them alike, and the medians of the paired ratios are the
figures to quote.

  ab.py renders ROUNDS SCENES [--same-image] LABEL=COMMAND [LABEL=COMMAND ...]
      Whole renders: each COMMAND is a pathtracer command line without scene
      and output (it may start with mpirun and its flags); SCENES a
      comma-separated list of shared CS184 scene names or .dae paths. Prints
      each variant's median render time (the end report's) and wall time
      (start to exit), and their paired ratios to the first variant's; with
      --same-image, fails unless every variant writes the first one's image
      in every round. E.g. two builds:
        F="-t 2 -s 64 -l 4 -m 5 -a 64 0 -r 480 360"
        /usr/bin/python3 scripts/ab.py renders 5 CBbunny,CBcoil,CBspheres_lambertian \\
            "main=/tmp/main/build/cli/pathtracer $F" "new=build/cli/pathtracer $F"
      or a setting (the sampler's cost):
        B=build/cli/pathtracer; F="-t 2 -s 64 -l 1 -m 5 -a 64 0 -r 480 360"
        /usr/bin/python3 scripts/ab.py renders 9 CBbunny,CBspheres_lambertian \\
            "independent=$B $F --sampler independent" "sobol=$B $F"

  ab.py bench A B FILTER [ROUNDS] [OUT]
      Two bench_trace commands (a binary, or a binary with its flags in one
      quoted argument) on the same benchmark filter, one repetition per run:
      per benchmark both medians (Mrays/s; builds/s for builds), the median
      and range of the paired ratios B/A, and nodes visited and triangles
      tested per ray; the raw runs in OUT.json. E.g.
        /usr/bin/python3 scripts/ab.py bench /tmp/main/build/bench/bench_trace build/bench/bench_trace \\
            'trace/CBbunny_x64/(diffuse|shadow)/(bvh4|embree_high_single)/' 5 out/ab
"""
import filecmp
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ptlib.paired import ratio_summary, round_order, run_rounds  # noqa: E402

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "scenes", "cs184")


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
    raw = []

    def measure(side, r):
        entries = run({"A": a, "B": b}[side], flt, f"{out}.{side}.json")
        raw.append({"round": r, "side": side, "benchmarks": entries})
        return rates(entries)

    runs = run_rounds(rounds, ["A", "B"], measure)
    with open(f"{out}.json", "w") as f:
        json.dump(raw, f)
    names = sorted(set().union(*runs["A"]) & set().union(*runs["B"]))
    if not names:
        sys.exit(f"ab.py: no benchmark matching {flt!r} ran in both builds (raw runs: {out}.json)")
    print(f"{'benchmark':64} {'A':>9} {'B':>9} {'B/A':>6} {'range':>13}  nodes A/B   tris A/B")
    for name in names:
        pairs = [(ra[name], rb[name]) for ra, rb in zip(runs["A"], runs["B"]) if name in ra and name in rb]
        sa, sb = [p[0] for p in pairs], [p[1] for p in pairs]
        ratio = ratio_summary([x[0] for x in sb], [x[0] for x in sa])
        scale = 1.0 if name.startswith("build/") else 1e6  # builds/s, else Mrays/s
        ma = statistics.median(x[0] for x in sa) / scale
        mb = statistics.median(x[0] for x in sb) / scale
        work = ""
        if sa[0][1] is not None and sb[0][1] is not None:
            work = f"  {sa[0][1]:.2f}/{sb[0][1]:.2f}"
            if sa[0][2] is not None:
                work += f"  {sa[0][2]:.2f}/{sb[0][2]:.2f}"
        unit = "" if not name.startswith("build/") else " (builds/s; B/tri)"
        print(f"{name + unit:64} {ma:9.3f} {mb:9.3f} {ratio.median:6.3f} {ratio.low:6.3f}-{ratio.high:.3f}{work}")


def scene_path(scene):
    return scene if scene.endswith(".dae") else os.path.join(SCENES, scene + ".dae")


def render(command, scene, output):
    """(render seconds from the end report, wall seconds from start to exit) of one render."""
    start = time.perf_counter()
    out = subprocess.run(shlex.split(command) + ["-f", output, scene_path(scene)], capture_output=True, text=True,
                         stdin=subprocess.DEVNULL, check=True).stdout
    wall = time.perf_counter() - start
    return float(re.search(r"Rendered in ([0-9.]+)", out).group(1)), wall


def renders_main(args):
    same_image = "--same-image" in args
    args = [a for a in args if a != "--same-image"]
    if len(args) < 3:
        sys.exit(__doc__)
    rounds, scenes = int(args[0]), args[1].split(",")
    variants = dict(a.split("=", 1) for a in args[2:])
    labels = list(variants)
    base = labels[0]
    times = {(scene, label): [] for scene in scenes for label in labels}  # (render s, wall s) per round
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(rounds):
            for scene in scenes:
                for label in round_order(labels, r):
                    t = render(variants[label], scene, os.path.join(tmp, label + ".png"))
                    times[(scene, label)].append(t)
                    print(f"run: round {r + 1} {scene} {label} {t[0]:.3f} s (wall {t[1]:.3f} s)", flush=True)
                if same_image:
                    for label in labels[1:]:
                        if not filecmp.cmp(os.path.join(tmp, base + ".png"), os.path.join(tmp, label + ".png"),
                                           shallow=False):
                            sys.exit(f"ab.py: {scene}: {label}'s image differs from {base}'s in round {r + 1}")
    print(f"{'scene':28} {'variant':16} {'median s':>9} {'ratio to ' + base:>18} {'range':>13} "
          f"{'wall s':>9} {'wall ratio':>11}")
    for scene in scenes:
        for label in labels:
            render_s, wall_s = ([x[i] for x in times[(scene, label)]] for i in (0, 1))
            r = ratio_summary(render_s, [x[0] for x in times[(scene, base)]])
            w = ratio_summary(wall_s, [x[1] for x in times[(scene, base)]])
            print(f"{scene:28} {label:16} {statistics.median(render_s):9.3f} {r.median:18.3f} "
                  f"{r.low:6.3f}-{r.high:.3f} {statistics.median(wall_s):9.3f} {w.median:11.3f}")
    if same_image:
        print("images: every variant wrote the first one's image in every round")


if __name__ == "__main__":
    modes = {"bench": bench_main, "renders": renders_main}
    if len(sys.argv) < 2 or sys.argv[1] not in modes:
        sys.exit(__doc__)
    modes[sys.argv[1]](sys.argv[2:])
