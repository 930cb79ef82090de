#!/usr/bin/python3
"""Compares this renderer with Cycles on one scene, from what cycles.sh made:

  compare_cycles.py DIR REFERENCE.pfm [--chart OUT.png] [--json OUT.json]

DIR holds cycles_converged.pfm, round*/cycles_s*.pfm with round*/cycles_times.json,
and round*/ours.csv (this renderer's convergence CSV against REFERENCE). Prints:
  - converged agreement of Cycles with the reference: image-mean ratio and the
    share of 8x8 blocks (mean over channels) within 0.5%, with the 5th-95th
    percentile of the block ratios (blocks black in both count as equal);
  - for each Cycles sample count, its MSE against the reference, and the
    equal-error time ratio: Cycles' wall time divided by the time this renderer
    takes to reach the same MSE (log-log interpolation of its curve), per round
    and the median over rounds.
Both errors are over every pixel and channel, as the pathtracer's
--convergence-csv computes them.
"""

import argparse
import csv
import glob
import json
import math
import os
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))  # scripts/: ptlib
from ptlib.images import read_pfm  # noqa: E402
from ptlib.paired import Summary  # noqa: E402

BLOCK = 8
TOLERANCE = 0.005


def block_means(img):
    h, w = img.shape[0] // BLOCK * BLOCK, img.shape[1] // BLOCK * BLOCK
    return img[:h, :w].mean(axis=2).reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean(axis=(1, 3))


def agreement(converged, reference):
    a, b = block_means(converged), block_means(reference)
    both_black = (a == 0) & (b == 0)
    lit = ~both_black & (b > 0)
    ratio = a[lit] / b[lit]
    within = np.count_nonzero(both_black) + np.count_nonzero(np.abs(ratio - 1) <= TOLERANCE)
    return {
        "mean_ratio": float(converged.mean() / reference.mean()),
        "blocks_within": within / a.size,
        "block_ratio_p5": float(np.percentile(ratio, 5)),
        "block_ratio_p95": float(np.percentile(ratio, 95)),
    }


def mse(img, reference):
    return float(np.mean((img.astype(np.float64) - reference) ** 2))


def read_curve(path):
    """(seconds, mse) of each row of a --convergence-csv file."""
    rows = list(csv.DictReader(open(path)))
    return [float(r["seconds"]) for r in rows], [float(r["rmse"]) ** 2 for r in rows], [int(r["spp"]) for r in rows]


def time_to_reach(seconds, errors, target):
    """Log-log interpolation of the time at which the curve reaches `target`;
    None when it never does."""
    for i in range(1, len(errors)):
        if errors[i] <= target:
            if errors[i - 1] <= target:
                return seconds[i - 1]
            t = (math.log(target) - math.log(errors[i - 1])) / (math.log(errors[i]) - math.log(errors[i - 1]))
            return math.exp(math.log(seconds[i - 1]) + t * (math.log(seconds[i]) - math.log(seconds[i - 1])))
    return seconds[0] if errors and errors[0] <= target else None


def main():
    p = argparse.ArgumentParser()
    p.add_argument("dir")
    p.add_argument("reference")
    p.add_argument("--chart")
    p.add_argument("--json")
    p.add_argument("--label", default="this renderer")
    args = p.parse_args()
    reference = read_pfm(args.reference).astype(np.float64)
    result = {"scene": os.path.basename(os.path.normpath(args.dir))}
    converged = os.path.join(args.dir, "cycles_converged.pfm")
    if os.path.exists(converged):
        result["agreement"] = agreement(read_pfm(converged).astype(np.float64), reference)
    rounds = sorted(glob.glob(os.path.join(args.dir, "round*")))
    per_spp = {}
    ours_curves = []
    for r in rounds:
        times = json.load(open(os.path.join(r, "cycles_times.json")))["seconds"]
        secs, errs, spps = read_curve(os.path.join(r, "ours.csv"))
        ours_curves.append((secs, errs, spps))
        for spp, t in times.items():
            e = mse(read_pfm(os.path.join(r, f"cycles_s{spp}.pfm")), reference)
            ours_t = time_to_reach(secs, errs, e)
            d = per_spp.setdefault(int(spp), {"mse": [], "cycles_seconds": [], "ours_seconds": [], "ratio": []})
            d["mse"].append(e)
            d["cycles_seconds"].append(min(t))
            d["ours_seconds"].append(ours_t)
            d["ratio"].append(min(t) / ours_t if ours_t else 0.0)
    result["equal_error"] = {}
    for spp, d in sorted(per_spp.items()):
        ratio = Summary(d["ratio"])  # each round's Cycles time over ours: the rounds alternate who goes first
        result["equal_error"][spp] = {
            "cycles_mse": statistics.median(d["mse"]),
            "cycles_seconds": statistics.median(d["cycles_seconds"]),
            "ours_seconds": statistics.median([t for t in d["ours_seconds"] if t] or [float("nan")]),
            "ratio_median": ratio.median,
            "ratio_range": [ratio.low, ratio.high],
        }
    scene = result["scene"]
    if "agreement" in result:
        a = result["agreement"]
        print(f"{scene}: converged agreement: image mean ratio (Cycles / reference) {a['mean_ratio']:.5f}; "
              f"8x8 blocks within 0.5%: {100 * a['blocks_within']:.1f}% (ratios {a['block_ratio_p5']:.4f}-"
              f"{a['block_ratio_p95']:.4f}, 5th-95th percentile)")
    for spp, d in result["equal_error"].items():
        lo, hi = d["ratio_range"]
        print(f"{scene}: Cycles {spp} spp: MSE {d['cycles_mse']:.3g} in {d['cycles_seconds']:.2f} s; "
              f"{args.label} reaches it in {d['ours_seconds']:.3f} s: {d['ratio_median']:.2f}x "
              f"({lo:.2f}-{hi:.2f} over {len(rounds)} rounds)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    if args.chart:
        draw_chart(args.chart, scene, ours_curves, result["equal_error"], args.label)


def draw_chart(path, scene, ours_curves, equal_error, label):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    n = min(len(c[0]) for c in ours_curves)
    secs = [statistics.median(c[0][i] for c in ours_curves) for i in range(n)]
    errs = [statistics.median(math.sqrt(c[1][i]) for c in ours_curves) for i in range(n)]
    ax.loglog(secs, errs, "o-", label=f"{label} (1..{ours_curves[0][2][n - 1]} spp)", color="C0")
    spps = sorted(equal_error)
    ax.loglog([equal_error[s]["cycles_seconds"] for s in spps], [math.sqrt(equal_error[s]["cycles_mse"]) for s in spps],
              "s--", label=f"Cycles ({', '.join(str(s) for s in spps)} spp)", color="C3")
    for s in spps:
        ax.annotate(f"{equal_error[s]['ratio_median']:.1f}x", (equal_error[s]["cycles_seconds"],
                                                               math.sqrt(equal_error[s]["cycles_mse"])),
                    textcoords="offset points", xytext=(6, 4), fontsize=8, color="C3")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("RMSE against the converged reference")
    ax.set_title(f"{scene}: error against time (labels: Cycles' time / ours at equal error)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
