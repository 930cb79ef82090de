#!/usr/bin/python3
"""Checks that two references of the same scene and settings, rendered by
different samplers, agree within their noise: a bias in either (for example
a sampler whose dimensions are correlated) shows as a non-zero mean
difference and per-pixel z-scores wider than N(0, 1). Prints the RMS and mean
difference over channels, and per pixel z = (Y_a - Y_b) / sqrt(var_a + var_b)
on illuminance: its mean, standard deviation, Stouffer's combined Z and the
fraction beyond 3.29 (0.1% under agreement).

Usage: /usr/bin/python3 compare_references.py A.pfm B.pfm (reads A.var.pfm, B.var.pfm)"""

import math
import sys

import numpy as np

from convergence_data import read_pfm, variance_path

LUMA = np.array([0.2126, 0.7152, 0.0722])


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, b = (read_pfm(p).astype(np.float64) for p in sys.argv[1:])
    var = sum(read_pfm(variance_path(p))[:, :, 0].astype(np.float64) for p in sys.argv[1:])
    d = a - b
    print(f"RMS difference {math.sqrt(float(np.mean(d * d))):.4g}, mean difference {float(np.mean(d)):.3g} "
          f"({float(np.mean(d)) / float(np.mean(b)) * 100:.3f}% of the mean)")
    noisy = var > 0
    z = ((a - b) @ LUMA)[noisy] / np.sqrt(var[noisy])
    print(f"per-pixel z over {z.size} pixels: mean {z.mean():.3f}, sd {z.std():.3f}, "
          f"Stouffer Z {z.sum() / math.sqrt(z.size):.2f}, beyond 3.29: {np.mean(np.abs(z) > 3.29) * 100:.2f}%")


if __name__ == "__main__":
    main()
