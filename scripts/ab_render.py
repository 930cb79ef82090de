"""Paired A/B of whole renders: variants (a pathtracer binary and its flags)
render each scene in alternation, the order reversed every other round, and
the render times (the end report's) are compared as paired ratios against the
first variant. On a shared, noisy machine the median of the paired ratios is
the figure to quote.

  python3 scripts/ab_render.py ROUNDS SCENES LABEL=COMMAND [LABEL=COMMAND ...]

SCENES is a comma-separated list of shared CS184 scene names; each COMMAND is
a pathtracer command line without scene and output (the scene and a scratch
output are appended). Example (the sampler's cost):

  B=build/io/cli/pathtracer; F="-t 2 -s 64 -l 1 -m 5 -a 64 0 -r 480 360"
  python3 scripts/ab_render.py 9 CBbunny,CBspheres_lambertian \\
      "independent=$B $F --sampler independent" "sobol=$B $F --sampler sobol"
"""

import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "scenes", "cs184")


def render_seconds(command, scene, output):
    out = subprocess.run(shlex.split(command) + ["-f", output, os.path.join(SCENES, scene + ".dae")],
                         capture_output=True, text=True, stdin=subprocess.DEVNULL, check=True).stdout
    return float(re.search(r"Rendered in ([0-9.]+)", out).group(1))


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    rounds, scenes = int(sys.argv[1]), sys.argv[2].split(",")
    variants = [a.split("=", 1) for a in sys.argv[3:]]
    times = {}
    with tempfile.TemporaryDirectory() as tmp:
        output = os.path.join(tmp, "image.png")
        for r in range(rounds):
            order = variants if r % 2 == 0 else variants[::-1]
            for scene in scenes:
                for label, command in order:
                    t = render_seconds(command, scene, output)
                    times.setdefault((scene, label), []).append(t)
                    print(f"run: round {r + 1} {scene} {label} {t:.3f} s", flush=True)
    base = variants[0][0]
    print(f"{'scene':28} {'variant':16} {'median s':>9} {'ratio to ' + base:>18} {'range':>13}")
    for scene in scenes:
        for label, _ in variants:
            ratios = [t / b for t, b in zip(times[(scene, label)], times[(scene, base)])]
            print(f"{scene:28} {label:16} {statistics.median(times[(scene, label)]):9.3f} "
                  f"{statistics.median(ratios):18.3f} {min(ratios):6.3f}-{max(ratios):.3f}")


if __name__ == "__main__":
    main()
