"""Reading what the convergence runs produce: the pathtracer's PFM images
(little-endian RGB, bottom row first), a reference's estimated noise, and the
combined per-scene CSV as one curve per method.
Shared by plot_convergence.py, efficiency_table.py, combine_reference.py and
compare_references.py; images through ptlib.images."""

import csv
import math
import os
import sys
from collections import OrderedDict

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))  # scripts/: ptlib
from ptlib.images import read_pfm, write_pfm  # noqa: E402,F401  (read_pfm, write_pfm: for the scripts beside it)


def variance_path(reference_path):
    """make_reference.sh stores X.pfm's variance image as X.var.pfm."""
    return reference_path[: -len(".pfm")] + ".var.pfm"


def reference_noise_rmse(reference_path):
    """Estimated RMSE of the reference itself, over pixels and channels: from
    the difference of its two halves (X.noise, written by
    combine_reference.py) when present; otherwise the square root of the mean
    of the variance image (each pixel's variance of its mean illuminance: an
    approximation of the per-channel noise, and an overestimate for
    stratified samplers)."""
    noise_file = reference_path[: -len(".pfm")] + ".noise"
    if os.path.exists(noise_file):
        return float(open(noise_file).read())
    var = read_pfm(variance_path(reference_path))[:, :, 0].astype(np.float64)
    return math.sqrt(float(np.mean(var)))


class Curve:
    """One method's rows, in order of increasing spp."""

    def __init__(self, family, method):
        self.family, self.method = family, method
        self.spp, self.seconds, self.rays, self.rmse, self.bias = [], [], [], [], []

    def rmse_at_spp(self, spp):
        return self.rmse[self.spp.index(spp)] if spp in self.spp else None


def read_curves(combined_csv):
    """Curves of a combined CSV (family,method,spp,seconds,rays,rmse,...)."""
    curves = OrderedDict()
    with open(combined_csv, newline="") as f:
        for row in csv.DictReader(f):
            c = curves.setdefault(row["method"], Curve(row["family"], row["method"]))
            c.spp.append(int(row["spp"]))
            c.seconds.append(float(row["seconds"]))
            c.rays.append(int(row["rays"]))
            c.rmse.append(float(row["rmse"]))
            c.bias.append(float(row["mean_bias"]))
    return curves
