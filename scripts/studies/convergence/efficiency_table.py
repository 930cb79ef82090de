#!/usr/bin/python3
"""Markdown tables of the convergence runs, one column per scene:
- efficiency 1 / (MSE x time), the median over each method's last three
  doublings (its highest sample counts), relative to the baseline method;
- the time each method needs to reach the RMSE that the baseline reaches
  with TARGET spp, interpolated on its log-log curve (or extrapolated along
  its last three points' slope when it stops short; "never" when its error no
  longer falls: a biased or blind estimator);
- each reference's sample count and estimated noise.

Usage: /usr/bin/python3 efficiency_table.py --spp-target 64 --reference-spp N [--baseline default]
           SCENE=COMBINED.csv=REFERENCE.pfm ...
"""

import argparse
import math
import statistics

from convergence_data import read_curves, reference_noise_rmse



def efficiency(curve, last=3):
    """Median over the last `last` points of 1 / (MSE x seconds)."""
    values = [1.0 / (r * r * t) for r, t in zip(curve.rmse[-last:], curve.seconds[-last:]) if r > 0 and t > 0]
    return statistics.median(values) if values else float("nan")


def log_slope(xs, ys):
    """Least-squares slope of log(ys) against log(xs)."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    den = sum((x - mx) ** 2 for x in lx)
    return sum((x - mx) * (y - my) for x, y in zip(lx, ly)) / den if den > 0 else 0.0


def time_to_reach(curve, target):
    """(seconds, how): how is 'interpolated', 'first point', 'extrapolated' or 'never'."""
    pts = list(zip(curve.seconds, curve.rmse))
    for i, (t, r) in enumerate(pts):
        if r <= target:
            if i == 0:
                return t, "first point"
            (t0, r0), (t1, r1) = pts[i - 1], pts[i]
            f = (math.log(target) - math.log(r0)) / (math.log(r1) - math.log(r0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), "interpolated"
    slope = log_slope(curve.seconds[-3:], curve.rmse[-3:])
    if slope > -0.2:  # Monte Carlo error falls as t^-0.5; this one has stopped falling
        return float("inf"), "never"
    t_last, r_last = pts[-1]
    return t_last * (target / r_last) ** (1.0 / slope), "extrapolated"


def format_seconds(t, how):
    if how == "never":
        return "never (error stops falling)"
    text = f"{t:.3g} s"
    return {"extrapolated": f"~{text} (extrapolated)", "first point": f"<= {text}"}.get(how, text)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp-target", type=int, default=64)
    ap.add_argument("--reference-spp", type=int, required=True)
    ap.add_argument("--baseline", default="default", help="the method every ratio is relative to")
    ap.add_argument("scenes", nargs="+", help="SCENE=COMBINED.csv=REFERENCE.pfm")
    args = ap.parse_args()
    BASELINE = args.baseline
    scenes = [s.split("=") for s in args.scenes]
    curves = {name: read_curves(path) for name, path, _ in scenes}
    methods = list(next(iter(curves.values())).keys())
    names = [name for name, _, _ in scenes]
    header = "| method | " + " | ".join(names) + " |\n|---|" + "---:|" * len(names)

    print(f"Efficiency 1 / (MSE x time) relative to `{BASELINE}` (median of the last three doublings, "
          f"{max(max(c.spp) for c in curves[names[0]].values()) // 4}..{max(curves[names[0]][BASELINE].spp)} spp; "
          f"higher is better; `{BASELINE}`'s absolute value in brackets, in 1 / (radiance^2 s)):\n")
    print(header)
    for m in methods:
        cells = []
        for n in names:
            base = efficiency(curves[n][BASELINE])
            e = efficiency(curves[n][m]) / base
            cells.append(f"{e:.2f}" + (f" ({base:.3g})" if m == BASELINE else ""))
        print(f"| {m} | " + " | ".join(cells) + " |")

    print(f"\nTime to reach the RMSE that `{BASELINE}` reaches with {args.spp_target} spp "
          f"(log-log interpolation of each curve; wall time, 2 threads):\n")
    print(header)
    targets = {n: curves[n][BASELINE].rmse_at_spp(args.spp_target) for n in names}
    print("| target RMSE | " + " | ".join(f"{targets[n]:.4g}" for n in names) + " |")
    for m in methods:
        print(f"| {m} | " + " | ".join(format_seconds(*time_to_reach(curves[n][m], targets[n])) for n in names) + " |")

    print(f"\nReferences: {args.reference_spp} spp of MIS direct light in two halves (Owen-scrambled Sobol, "
          "wavefront engine, seeds 1000003 and 1000004), averaged; noise = RMSE of the average, estimated as "
          "rms(half1 - half2) / 2:\n")
    print("| | " + " | ".join(names) + " |\n|---|" + "---:|" * len(names))
    noise = {n: reference_noise_rmse(ref) for n, _, ref in scenes}
    lowest = {n: min(min(c.rmse) for c in curves[n].values()) for n in names}
    print("| reference noise RMSE (est.) | " + " | ".join(f"{noise[n]:.3g}" for n in names) + " |")
    print("| lowest plotted RMSE | " + " | ".join(f"{lowest[n]:.3g}" for n in names) + " |")
    print("| ratio | " + " | ".join(f"{lowest[n] / noise[n]:.1f}x" for n in names) + " |")


if __name__ == "__main__":
    main()
