#!/usr/bin/python3
"""Draws one scene's convergence chart: RMSE against the reference (log)
over wall time (log), one line per method, points at each doubling of the
samples per pixel. Horizontal guides: the baseline method's 64-spp RMSE (the
target of the time-to-target table) and the reference's own estimated noise.

Usage: /usr/bin/python3 plot_convergence.py COMBINED.csv REFERENCE.pfm OUT.png [BASELINE]"""

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from convergence_data import read_curves, reference_noise_rmse  # noqa: E402

LINESTYLES = {"direct": "-", "sampler": "--", "adaptive": ":", "roulette": "-.", "engine": (0, (6, 2))}
TARGET_SPP = 64


def draw(combined_csv, reference_pfm, out_png, baseline="default"):
    curves = read_curves(combined_csv)
    scene = os.path.basename(combined_csv)[len("convergence_"):-len(".csv")]
    fig, ax = plt.subplots(figsize=(9, 5.6))
    colours = plt.get_cmap("tab20").colors
    for i, c in enumerate(curves.values()):
        ax.loglog(c.seconds, c.rmse, linestyle=LINESTYLES.get(c.family, "-"), marker="o", markersize=3,
                  linewidth=2.2 if c.method == baseline else 1.4, color=colours[(2 * i) % 20 + (i // 10) % 2],
                  label=f"{c.method} ({c.family})")
    base = curves.get(baseline)
    if base and base.rmse_at_spp(TARGET_SPP) is not None:
        ax.axhline(base.rmse_at_spp(TARGET_SPP), color="black", linestyle=":", linewidth=0.9,
                   label=f"{baseline} at {TARGET_SPP} spp")
    noise = reference_noise_rmse(reference_pfm)
    ax.axhline(noise, color="grey", linestyle="--", linewidth=0.9, label="reference's own noise (est.)")
    ax.set_xlabel("wall time, seconds (log; 2 threads, shared machine)")
    ax.set_ylabel("RMSE against the reference (log)")
    max_spp = max(max(c.spp) for c in curves.values())
    ax.set_title(f"{scene}: error against time, 1..{max_spp} spp per method")
    ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, frameon=False)
    fig.tight_layout()
    fig.savefig(out_png, dpi=100)
    print(f"plot_convergence: wrote {out_png}")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    draw(*sys.argv[1:])
