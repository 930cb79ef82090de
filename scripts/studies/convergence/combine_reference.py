#!/usr/bin/python3
"""Combines the two independent halves of a reference (same settings,
different seeds) into the reference: their average (PFM), the per-pixel
variance of that average from the halves' own variance images ((v1 + v2) / 4,
a grey PFM; an overestimate for stratified samplers such as Owen-scrambled
Sobol), and its noise: the RMSE of the average over pixels and channels,
estimated from the halves' difference as rms(half1 - half2) / 2, which holds
for any unbiased sampler.

Usage: /usr/bin/python3 combine_reference.py HALF1.pfm HALF2.pfm OUT.pfm
       (reads HALFn.var.pfm; writes OUT.var.pfm and OUT.noise)"""

import math
import sys

import numpy as np

from convergence_data import read_pfm, variance_path, write_pfm


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    half1, half2, out = sys.argv[1:]
    a = read_pfm(half1).astype(np.float64)
    b = read_pfm(half2).astype(np.float64)
    va = read_pfm(variance_path(half1)).astype(np.float64)
    vb = read_pfm(variance_path(half2)).astype(np.float64)
    write_pfm(out, (a + b) / 2)
    write_pfm(variance_path(out), (va + vb) / 4)
    noise = math.sqrt(float(np.mean((a - b) ** 2))) / 2
    with open(out[: -len(".pfm")] + ".noise", "w") as f:
        f.write(f"{noise:.9g}\n")
    print(f"combine_reference: {out}, noise RMSE {noise:.4g} (from the halves' difference)", file=sys.stderr)


if __name__ == "__main__":
    main()
