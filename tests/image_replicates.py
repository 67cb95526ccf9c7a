"""What the scene checks compute from a report's replicate images, apart from pcbench's code: the
whole image's channel means per replicate, and Student's t distribution."""

import math
import os
import sys

import numpy as np
import OpenImageIO as oiio


def incomplete_beta(a, b, x):
    """The regularised incomplete beta function I_x(a, b) (continued fraction, Lentz)."""
    if x <= 0.0 or x >= 1.0:
        return 0.0 if x <= 0.0 else 1.0
    if x > (a + 1.0) / (a + b + 2.0):
        return 1.0 - incomplete_beta(b, a, 1.0 - x)
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) +
                     a * math.log(x) + b * math.log(1.0 - x)) / a
    tiny = 1e-300
    c, d = 1.0, 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    f = d
    for m in range(1, 500):
        for numerator in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                          -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1.0 + numerator * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + numerator / c
            c = c if abs(c) > tiny else tiny
            f *= c * d
        if abs(c * d - 1.0) < 1e-15:
            break
    return front * f


def student_two_sided_p(t, dof):
    return incomplete_beta(dof / 2.0, 0.5, dof / (dof + t * t))


def replicate_channel_means(folder, run):
    """One row per replicate: the mean of each of R, G, B over the whole image."""
    rows = []
    for name in run["image"]["files"]["replicates"]:
        image = oiio.ImageInput.open(os.path.join(folder, name))
        if image is None:
            sys.exit(f"cannot read {name}: {oiio.geterror()}")
        pixels = image.read_image(format="float").astype(np.float64)
        image.close()
        rows.append(pixels[:, :, :3].reshape(-1, 3).mean(0))
    return np.array(rows)
