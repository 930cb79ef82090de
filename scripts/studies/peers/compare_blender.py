"""Compares this renderer's render of a Blender export with Cycles' render of
the same scene, from what blender_scenes.sh made:

  compare_blender.py OURS.pfm CYCLES_HALF_A.pfm CYCLES_HALF_B.pfm [--json OUT.json]

Cycles' image is the mean of its two halves (two seeds, the same samples
each). Prints, and checks against the targets:
  - the image-mean ratio, ours / Cycles: within 1%;
  - the 8x8 block ratios (mean over channels), ours / Cycles, against the
    spread of Cycles' own halves, half A / half B: the 5th-95th percentile
    range of ours / Cycles must lie within that of A / B. Blocks darker than
    1% of the image mean in Cycles' image are left out (their ratios are noise).
Exit status 1 when a target is missed.
"""

import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
from ptlib.images import read_pfm  # noqa: E402

BLOCK = 8


def block_means(img):
    h, w = img.shape[0] // BLOCK * BLOCK, img.shape[1] // BLOCK * BLOCK
    return img[:h, :w].mean(axis=2).reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean(axis=(1, 3))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("ours")
    p.add_argument("half_a")
    p.add_argument("half_b")
    p.add_argument("--json")
    args = p.parse_args()
    ours = read_pfm(args.ours).astype(np.float64)
    a, b = (read_pfm(x).astype(np.float64) for x in (args.half_a, args.half_b))
    if ours.shape != a.shape or a.shape != b.shape:
        raise SystemExit(f"compare_blender: image sizes differ: {ours.shape}, {a.shape}, {b.shape}")
    cycles = 0.5 * (a + b)
    mean_ratio = ours.mean() / cycles.mean()
    bo, bc, ba, bb = (block_means(x) for x in (ours, cycles, a, b))
    lit = bc > 0.01 * cycles.mean()
    lit &= (ba > 0) & (bb > 0)
    ours_ratio, halves_ratio = bo[lit] / bc[lit], ba[lit] / bb[lit]
    o5, o95 = np.percentile(ours_ratio, [5, 95])
    h5, h95 = np.percentile(halves_ratio, [5, 95])
    result = {
        "mean_ratio": float(mean_ratio),
        "blocks": int(lit.sum()),
        "ours_p5": float(o5), "ours_p95": float(o95),
        "halves_p5": float(h5), "halves_p95": float(h95),
        "mean_ok": bool(abs(mean_ratio - 1) <= 0.01),
        "blocks_ok": bool(o5 >= h5 and o95 <= h95),
    }
    name = os.path.basename(args.ours)
    print(f"{name}: mean ours/Cycles {mean_ratio:.4f} ({'ok' if result['mean_ok'] else 'MISSED'}); "
          f"8x8 block ratios 5-95%: ours/Cycles {o5:.4f}-{o95:.4f}, Cycles' halves {h5:.4f}-{h95:.4f} "
          f"({'ok' if result['blocks_ok'] else 'MISSED'}; {result['blocks']} blocks)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    return 0 if result["mean_ok"] and result["blocks_ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
