#!/usr/bin/python3
"""The course renderer's image next to this renderer's default and
--cs184-compat renders of the same settings, and the ratio of the default to
the course's per 8x8 block: docs/course_quirks_<scene>.png, and one line of
numbers per image.

    /usr/bin/python3 scripts/studies/course/compare_course.py COURSE.png DEFAULT.pfm COMPAT.pfm OUT.png

Decoding of the course's PNG: each channel is floor(255 (L sqrt 2)^(1/2.2)),
so a code v stands for [v, v + 1) / 255 and is decoded at its middle (0 at 0).
The 48 x 5 watermark and saturated pixels are left out of the statistics.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))  # scripts/: ptlib
from ptlib.images import read_pfm, read_png  # noqa: E402

LUMA = np.array([0.2126, 0.7152, 0.0722])


def decode_course(path):
    codes = read_png(path)[:, :, :3].astype(np.float64)
    linear = np.where(codes == 0, 0.0, ((codes + 0.5) / 255.0) ** 2.2 / np.sqrt(2.0))
    mask = ~(codes >= 255).any(axis=2)
    mask[-5:, :48] = False
    return linear, mask


def to_display(linear):
    return np.clip((linear * np.sqrt(2.0)) ** (1 / 2.2), 0, 1)


def block_ratio(a, b, mask, block=8):
    h, w = mask.shape
    out = np.full((h // block, w // block), np.nan)
    for by in range(h // block):
        for bx in range(w // block):
            s = np.s_[by * block:(by + 1) * block, bx * block:(bx + 1) * block]
            m = mask[s]
            if m.sum() >= block * block // 2 and b[s][m].mean() > 1e-4:
                out[by, bx] = a[s][m].mean() / b[s][m].mean()
    return out


def main(course_png, default_pfm, compat_pfm, out_png):
    course, mask = decode_course(course_png)
    default, compat = read_pfm(default_pfm).astype(np.float64), read_pfm(compat_pfm).astype(np.float64)
    y = lambda img: img @ LUMA  # noqa: E731
    for name, img in (("default", default), ("compat", compat)):
        print(f"{name}: mean illuminance / course's {y(img)[mask].mean() / y(course)[mask].mean():.4f}")
    ratio = block_ratio(y(default), y(course), mask)
    fig, axes = plt.subplots(1, 4, figsize=(16, 3.6))
    for ax, (title, img) in zip(axes, (("course renderer", course), ("default (physical)", default),
                                       ("--cs184-compat", compat))):
        ax.imshow(to_display(img), interpolation="nearest")
        ax.set_title(title)
        ax.axis("off")
    im = axes[3].imshow(ratio, cmap="coolwarm", vmin=0.4, vmax=1.6, interpolation="nearest")
    axes[3].set_title("default / course, 8x8 blocks")
    axes[3].axis("off")
    fig.colorbar(im, ax=axes[3], fraction=0.046)
    fig.tight_layout()
    fig.savefig(out_png, dpi=80)


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    main(*sys.argv[1:5])
