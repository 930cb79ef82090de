#!/usr/bin/python3
"""Splits a ray file (trace_rays' format: float32 ox, oy, oz, tmin, dx, dy, dz,
tmax per ray) by where each ray starts, so that trace_rays can time each kind
apart: on one of the six faces of the scene's bounds (a Cornell box's walls:
`x-`, `x+`, `y-`, `y+`, `z-`, `z+`: the nearest face, if it lies within EPS,
by default 1e-4 of the bounds' diagonal), or inside (`inner`, as are NaN
origins). With --box, the rays that start on a face are split further by
whether their segment [tmin, tmax] enters that box (`_box`) or not. The
bounds are those of the triangle file (float32, 9 per triangle). Queue order
is kept within each subset.

  rays_by_origin.py SCENE.tris RAYS.rays OUT_PREFIX [--box x0 y0 z0 x1 y1 z1] [--eps E]

E.g. the later shadow rays of a CBbunny render, those from the floor split by
whether they cross the bunny's box:
  pathtracer -t 1 -s 4 -l 4 -m 5 -r 480 360 -a 64 0 --cs184-framing --dump-queues q CBbunny.dae
  /usr/bin/python3 scripts/studies/rays_by_origin.py q/scene.tris q/shadow_d1.rays q/d1 \\
      --box -0.386 0.0 -0.290 0.392 0.774 0.307
  for f in q/d1_*.rays; do trace_rays q/scene.tris "$f" --occluded --threads 1; done
"""
import argparse
import array
import sys


def read_floats(path, per_item, what):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) % (4 * per_item):
        sys.exit(f"rays_by_origin: {path}: not a whole number of {per_item}-float {what}")
    values = array.array("f")
    values.frombytes(data)
    if sys.byteorder == "big":  # the files are little-endian
        values.byteswap()
    return values


def bounds_of(tris):
    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    for i in range(0, len(tris) - len(tris) % 3, 3):
        for a in range(3):
            lo[a] = min(lo[a], tris[i + a])
            hi[a] = max(hi[a], tris[i + a])
    return lo, hi


def segment_enters(org, d, t0, t1, lo, hi):
    for a in range(3):
        if d[a] == 0.0:
            if not lo[a] <= org[a] <= hi[a]:
                return False
            continue
        ta, tb = (lo[a] - org[a]) / d[a], (hi[a] - org[a]) / d[a]
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
        if t0 > t1:
            return False
    return True


def main():
    p = argparse.ArgumentParser(description="Split a ray file by where its rays start.")
    p.add_argument("tris")
    p.add_argument("rays")
    p.add_argument("prefix")
    p.add_argument("--box", type=float, nargs=6, metavar=("X0", "Y0", "Z0", "X1", "Y1", "Z1"))
    p.add_argument("--eps", type=float, help="distance from a face that counts as on it (1e-4 of the diagonal)")
    args = p.parse_args()
    tris = read_floats(args.tris, 9, "triangles")
    if not tris:
        sys.exit(f"rays_by_origin: {args.tris}: no triangles")
    lo, hi = bounds_of(tris)
    eps = args.eps if args.eps is not None else 1e-4 * sum((h - l) ** 2 for l, h in zip(lo, hi)) ** 0.5
    if args.box and any(args.box[a] > args.box[a + 3] for a in range(3)):
        sys.exit("rays_by_origin: --box: each lower corner coordinate must not exceed the upper one")
    rays = read_floats(args.rays, 8, "rays")
    subsets = {}
    for i in range(0, len(rays), 8):
        r = rays[i:i + 8]
        org = r[0:3]
        distance, face = min((abs(org[a] - bound[a]), "xyz"[a] + sign)
                             for a in range(3) for bound, sign in ((lo, "-"), (hi, "+")))
        name = face if distance <= eps and all(c == c for c in org) else "inner"
        if args.box and name != "inner":
            crosses = segment_enters(org, r[4:7], r[3], r[7], args.box[0:3], args.box[3:6])
            name += "_box" if crosses else "_clear"
        subsets.setdefault(name, array.array("f")).extend(r)
    total = len(rays) // 8
    for name, values in sorted(subsets.items()):
        path = f"{args.prefix}_{name}.rays"
        with open(path, "wb") as f:
            values.tofile(f)
        print(f"{path}: {len(values) // 8} rays ({100.0 * len(values) / 8 / total:.1f}%)")


if __name__ == "__main__":
    main()
