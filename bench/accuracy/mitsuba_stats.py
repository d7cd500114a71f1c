"""Image means and 16 x 16 block means (a low-pass) of igi and Mitsuba renders, two seeds each:
the igi - Mitsuba difference in units of its standard error, estimated from the seed-to-seed
spread of each renderer. usage: mitsuba_stats.py WORK_DIR"""
import sys
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
work = Path(sys.argv[1])


def load(name):
    return np.array(mi.Bitmap(str(work / name)), dtype=np.float64)[:, :, :3].mean(axis=2)


def blocks(image, size=16):
    h, w = image.shape[0] // size, image.shape[1] // size
    return image[: h * size, : w * size].reshape(h, size, w, size).mean(axis=(1, 3))


igi = [load(f"igi_{s}.exr") for s in (0, 1)]
mitsuba = [load(f"mitsuba_{s}.exr") for s in (0, 1)]
# Pixels are independent estimates in both renderers, so the variance of a block mean is the sum
# of its pixels' variances over (pixels per block)^2; a pixel's variance is estimated from its
# two runs as (x0 - x1)^2 / 2, which pools hundreds of degrees of freedom per block.
def pixel_variance(runs):
    return (runs[0] - runs[1]) ** 2 / 2


for name, size in (("image mean", None), ("16x16 blocks", 16)):
    reduce = (lambda i: np.array([i.mean()])) if size is None else (lambda i: blocks(i, size))
    count = igi[0].size if size is None else size * size
    a = reduce((igi[0] + igi[1]) / 2)
    b = reduce((mitsuba[0] + mitsuba[1]) / 2)
    # Variance of the two-run average of a block: pixel variances summed per block, / count^2, / 2 runs.
    variance = (reduce(pixel_variance(igi)) + reduce(pixel_variance(mitsuba))) / count / 2
    difference = a - b
    z2 = np.mean(difference ** 2 / np.maximum(variance, 1e-30))
    print(f"{name}: igi {a.mean():.6f}, mitsuba {b.mean():.6f}, relative difference {difference.mean() / b.mean():+.4%}, "
          f"mean z^2 {z2:.2f} over {difference.size} values, largest |z| {np.sqrt((difference ** 2 / np.maximum(variance, 1e-30)).max()):.2f}")
