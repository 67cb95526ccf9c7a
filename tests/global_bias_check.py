#!/usr/bin/python3
"""A small global bias that the 8x8 tiles miss and the whole image catches (issue 25, item 4).

Usage:
    /usr/bin/python3 tests/global_bias_check.py PATH/TO/pcbench [--seeds 1,2,3,4,5]

ctl-scene-nee-count is path tracing whose next-event estimates are divided by 1 + severity
(estimators/scene/ctl_scene_nee_count.cpp): the image is low by severity / (1 + severity) x 98.7%
on cornell, nearly uniformly. For each seed, `pcbench verify -e ctl-scene-nee-count
--replicate-images --seed S` renders it and plain at its declared workload (cornell at 128x128,
1 spp x 16 replicates), and the check reads the report:
  - the 8x8 tile comparison with plain does not flag it (`consistent`, where `biased` is
    expected, so verify exits 1), and its tile_relative_mdb exceeds the bias the image shows;
  - Welch's t on the replicates' whole-image channel means (images/<id>_rep<k>.exr), Holm over
    the 3 channels, flags it below ALPHA / PYRAMID_TESTS: the strictest step of a Holm family of
    blocks of 8, 16, ..., 128 pixels over 3 channels, so a test of block means up to the whole
    image would flag it too;
  - the image's relative difference is the derived bias within 4 standard errors.
Then once at severity 0 (pt bit for bit): the tiles and the whole image both consistent.
Prints one line per check and "N passed, M failed"; exits 1 if any check failed.
"""

import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

CONTROL = "ctl-scene-nee-count"
PARTNER = "plain"
SEVERITY = 0.015            # the control's default
NEXT_EVENT_SHARE = 0.987    # of cornell's image (pcbench run -e pt --strategy-images)
ALPHA = 0.01
PYRAMID_TESTS = 3 * (256 + 64 + 16 + 4 + 1)  # 128x128: blocks of 8, 16, 32, 64, 128 pixels

passed = 0
failed = 0


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
    print(("ok   " if ok else "FAIL ") + what)


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
            sys.exit(f"global_bias_check: cannot read {name}: {oiio.geterror()}")
        pixels = image.read_image(format="float").astype(np.float64)
        image.close()
        rows.append(pixels[:, :, :3].reshape(-1, 3).mean(0))
    return np.array(rows)


def whole_image_welch(folder, report, a, b):
    """Welch's t per channel between runs a and b's whole-image replicate means: (relative
    difference mean_a / mean_b - 1 over the channels' sum, its standard error, the Holm-adjusted
    smallest p over the channels)."""
    runs = {r["estimator"]: r for r in report["runs"]}
    x, y = replicate_channel_means(folder, runs[a]), replicate_channel_means(folder, runs[b])
    p = []
    for c in range(3):
        va, vb = x[:, c].var(ddof=1) / len(x), y[:, c].var(ddof=1) / len(y)
        t = (x[:, c].mean() - y[:, c].mean()) / math.sqrt(va + vb)
        dof = (va + vb) ** 2 / (va ** 2 / (len(x) - 1) + vb ** 2 / (len(y) - 1))
        p.append(student_two_sided_p(t, dof))
    sa, sb = x.sum(1), y.sum(1)
    relative = sa.mean() / sb.mean() - 1.0
    stderr = math.sqrt(sa.var(ddof=1) / len(sa) + sb.var(ddof=1) / len(sb)) / sb.mean()
    return relative, stderr, min(1.0, 3 * min(p))


def verify(pcbench, folder, seed, severity=None):
    args = [pcbench, "verify", "-e", CONTROL, "--replicate-images", "--seed", str(seed), "-q",
            "--out", folder]
    if severity is not None:
        args += ["-p", f"severity={severity}"]
    proc = subprocess.run(args, capture_output=True, text=True)
    path = os.path.join(folder, "report.json")
    if not os.path.exists(path):
        check(False, f"verify wrote a report (exit {proc.returncode}: {proc.stderr[-300:]})")
        return None, None
    with open(path) as f:
        report = json.load(f)
    tiles = [c for c in report["comparisons"] if c["test"] == "tile-welch-holm"]
    if len(tiles) != 1:
        check(False, f"one tile comparison ({len(tiles)})")
        return None, None
    return report, tiles[0]


def main():
    pcbench = sys.argv[1]
    seeds = [1, 2, 3, 4, 5]
    if "--seeds" in sys.argv:
        seeds = [int(s) for s in sys.argv[sys.argv.index("--seeds") + 1].split(",")]
    threshold = ALPHA / PYRAMID_TESTS
    expected = -SEVERITY / (1.0 + SEVERITY) * NEXT_EVENT_SHARE
    with tempfile.TemporaryDirectory() as root:
        for seed in seeds:
            folder = os.path.join(root, f"seed{seed}")
            report, tiles = verify(pcbench, folder, seed)
            if report is None:
                continue
            relative, stderr, p = whole_image_welch(folder, report, CONTROL, PARTNER)
            check(tiles["result"] == "consistent" and tiles["expect"] == "biased" and
                  tiles["tile_relative_mdb"] > abs(relative),
                  f"seed {seed}: 8x8 tiles miss it: {tiles['result']} (Holm-adjusted p "
                  f"{tiles['p_adjusted']:.3g}), tile_relative_mdb {tiles['tile_relative_mdb']:.1%}"
                  f" > |bias| {abs(relative):.2%}")
            check(p < threshold, f"seed {seed}: the whole image flags it: p = {p:.3g} < "
                  f"{ALPHA} / {PYRAMID_TESTS} = {threshold:.2g}")
            check(abs(relative - expected) < 4 * stderr,
                  f"seed {seed}: image bias {relative:+.3%} ± {stderr:.3%}, derived "
                  f"{expected:+.3%}")
        folder = os.path.join(root, "severity0")
        report, tiles = verify(pcbench, folder, seeds[0], severity=0)
        if report is not None:
            relative, stderr, p = whole_image_welch(folder, report, CONTROL, PARTNER)
            check(tiles["result"] == "consistent",
                  f"severity 0: 8x8 tiles consistent (p {tiles['p_adjusted']:.3g})")
            check(p >= threshold, f"severity 0: the whole image consistent: difference "
                  f"{relative:+.3%} ± {stderr:.3%}, p = {p:.3g} >= {threshold:.2g}")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
