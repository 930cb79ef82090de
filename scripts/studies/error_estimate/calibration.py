#!/usr/bin/python3
"""The render's own error estimate against the true error, per scene, depth and
sample count: a reference per scene and depth (make_reference.sh: two halves of
independent seeds, its own noise from their difference), then one convergence
run (--convergence-csv) per scene and depth with another seed, whose rows carry
the RMSE against the reference and the render's estimate (est_rmse). The
reference's noise is taken out of the measured RMSE (independent renders add
their mean squared errors). Writes a results record (kind "table") that
scripts/results.py reads.

  calibration.py OUT.json [--scenes A,B] [--width W --height H] [--ref-spp N] [--threads T]
                 [--scene-dir DIR] [--spp 16,64,256] [--depths 1,5]
"""
import argparse
import csv
import io
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from ptlib import results  # noqa: E402

CONVERGENCE_SCENES = "CBbunny,CBcoil,CBempty,CBgems,CBspheres_lambertian,CBspheres_microfacet_al_ag,bunny"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--scenes", default=CONVERGENCE_SCENES)
    ap.add_argument("--scene-dir", default=os.path.join(ROOT, "..", "shared", "scenes", "cs184"))
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--ref-spp", type=int, default=8192)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--spp", default="16,64,256")
    ap.add_argument("--depths", default="1,5")
    a = ap.parse_args()
    pathtracer = os.environ.get("PATHTRACER", os.path.join(ROOT, "build", "cli", "pathtracer"))
    counts = [int(s) for s in a.spp.split(",")]
    rows = []
    for scene in a.scenes.split(","):
        path = os.path.join(a.scene_dir, scene + ".dae")
        if not os.path.exists(path):
            sys.exit(f"calibration: {path} not found")
        for depth in (int(d) for d in a.depths.split(",")):
            ref = subprocess.run(["bash", os.path.join(ROOT, "scripts", "studies", "convergence", "make_reference.sh"),
                                  path, str(a.width), str(a.height), str(depth), str(a.ref_spp), "1000003",
                                  str(a.threads)], check=True, capture_output=True, text=True).stdout.strip()
            noise = float(open(ref[: -len(".pfm")] + ".noise").read())
            csv_path = f"{a.out}.{scene}_m{depth}.csv"
            subprocess.run([pathtracer, "-t", str(a.threads), "-m", str(depth), "-l", "1", "-r", str(a.width),
                            str(a.height), "-s", str(max(counts)), "-q", "--reference", ref, "--convergence-csv",
                            csv_path, path], check=True)
            for r in csv.DictReader(io.StringIO(open(csv_path).read())):
                spp = int(r["spp"])
                if spp not in counts or not r["est_rmse"]:
                    continue
                measured, estimate = float(r["rmse"]), float(r["est_rmse"])
                truth = math.sqrt(max(0.0, measured * measured - noise * noise))
                ratio = estimate / truth if truth > 0 else float("inf")
                rows.append([scene, depth, spp, f"{truth:.5g}", f"{estimate:.5g}", f"{ratio:.3f}"])
                print(f"{scene} -m {depth} {spp} spp: true {truth:.4g}, estimate {estimate:.4g}, ratio {ratio:.3f}")
            os.remove(csv_path)
    ratios = [float(r[5]) for r in rows]
    inside = sum(0.8 <= x <= 1.25 for x in ratios)
    command = "python3 scripts/studies/error_estimate/calibration.py " + " ".join(sys.argv[1:])
    rec = results.new(
        "table", "The render's own error estimate against the true RMSE (whole image)", command, "",
        notes=(f"{a.width}x{a.height}, -l 1 -t {a.threads}, default sampler (Owen-scrambled Sobol) and estimators; "
               f"references of {a.ref_spp} spp with other seeds, their noise taken out of the true RMSE. "
               f"{inside} of {len(ratios)} ratios in [0.8, 1.25]; all in [{min(ratios):.3f}, {max(ratios):.3f}]."),
        tables=[{"columns": ["scene", "-m", "spp", "true RMSE", "estimated RMSE", "estimate / true"], "rows": rows}])
    results.save(a.out, rec)
    print(f"calibration: {inside} of {len(ratios)} ratios in [0.8, 1.25]; wrote {a.out}")


if __name__ == "__main__":
    main()
