#!/usr/bin/env python3
"""Verify replicate images held in numpy arrays, as a renderer's Python script would.

Two sets of 16 replicates of a 64x48 image are made in numpy: `honest`, noise around the
true image, and `biased`, the same with a 3% bias in one 8x8 block (a bug that touches a few
pixels). pcbench tests each set against the true image and the two sets against each other,
block by block at every scale, and flags the bias. Exits 1 if a verdict is not the expected one.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/verify_from_arrays.py
"""

import sys

import numpy as np

import pcbench

rng = np.random.default_rng(2015)
height, width, replicates = 48, 64, 16
y, x = np.mgrid[0:height, 0:width]
truth = (1.0 + 0.5 * np.cos(x / 9.0) * np.sin(y / 7.0))[..., None] * np.array([1.0, 0.7, 0.4])


def render(count, bias=0.0):
    """count independent replicates: the truth with 10% noise per pixel; a bias in one block."""
    images = truth * (1.0 + 0.1 * rng.standard_normal((count, height, width, 3)))
    images[:, 16:24, 32:40, :] *= 1.0 + bias
    return images.astype(np.float32)


honest = render(replicates)
biased = render(replicates, bias=0.03)

checks = [
    ("honest vs the truth", pcbench.verify_images(honest, reference=truth), "consistent"),
    ("biased vs the truth", pcbench.verify_images(biased, reference=truth), "biased"),
    ("biased vs honest", pcbench.verify_images(biased, against=honest), "biased"),
]
ok = True
for label, result, expected in checks:
    tiles = result.scales.iloc[0]
    print(f"{label:22s} {result.verdict:11s} adjusted p {result.p_adjusted:.3g}; detectable "
          f"bias per {tiles['block']:.0f}x{tiles['block']:.0f} tile "
          f"{100 * tiles['relative_mdb']:.1f}%, blocks differing "
          f"{list(result.scales['blocks_differing'])}")
    ok = ok and result.verdict == expected
print(checks[2][1].scales[["block", "tests", "blocks_differing", "relative_mdb",
                           "samples_factor_for_required_mdb"]].to_string(index=False))
sys.exit(0 if ok else 1)
