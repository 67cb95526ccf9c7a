#!/usr/bin/python3
"""A small global bias that the 8x8 tiles miss and the whole image catches (issue 25, item 4).

Usage:
    /usr/bin/python3 tests/global_bias_check.py PATH/TO/pcbench [--seeds 1,2,3,4,5]

ctl-scene-nee-count is path tracing whose next-event estimates are divided by 1 + severity
(estimators/scene/ctl_scene_nee_count.cpp): the image is low by severity / (1 + severity) x 98.7%
on cornell, nearly uniformly. For each seed, `pcbench verify -e ctl-scene-nee-count
--replicate-images --seed S` renders it and plain at its declared workload (cornell at 128x128,
1 spp x 16 replicates), and the check reads the report:
  - verify exits 0: the block pyramid flags the control, and the coarsest scale that differs is
    the whole image;
  - the 8x8 scale alone does not (no block differs), and its detectable bias exceeds the bias the
    image shows;
  - apart from the pyramid's code, Welch's t on the replicates' whole-image channel means
    (images/<id>_rep<k>.exr) is below the image scale's share of alpha, and where the image scale
    decides the comparison, its p-value times the pyramid's weight, L scales x 3 channels, is the
    comparison's adjusted p;
  - the image's relative difference is the derived bias within 4 standard errors.
Then once at severity 0 (pt bit for bit): no scale differs (verify exits 1, the control missed)
and the whole image's Welch p is above ALPHA.
Prints one line per check and "N passed, M failed"; exits 1 if any check failed.
"""

import json
import math
import os
import subprocess
import sys
import tempfile

from check_log import check, summary
from image_replicates import replicate_channel_means, student_two_sided_p

CONTROL = "ctl-scene-nee-count"
PARTNER = "plain"
SEVERITY = 0.015            # the control's default
NEXT_EVENT_SHARE = 0.987    # of cornell's image (pcbench run -e pt --strategy-images)
ALPHA = 0.01


def whole_image_welch(folder, report, a, b):
    """Welch's t per channel between runs a and b's whole-image replicate means: (relative
    difference mean_a / mean_b - 1 over the channels' sum, its standard error, the smallest p over
    the channels)."""
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
    return relative, stderr, min(p)


def verify(pcbench, folder, seed, severity=None):
    """The report and its one block-pyramid comparison of the control with its partner, and
    verify's exit status."""
    args = [pcbench, "verify", "-e", CONTROL, "--replicate-images", "--seed", str(seed), "-q",
            "--out", folder]
    if severity is not None:
        args += ["-p", f"severity={severity}"]
    proc = subprocess.run(args, capture_output=True, text=True)
    path = os.path.join(folder, "report.json")
    if not os.path.exists(path):
        check(False, f"verify wrote a report (exit {proc.returncode}: {proc.stderr[-300:]})")
        return None, None, proc.returncode
    with open(path) as f:
        report = json.load(f)
    pyramids = [c for c in report["comparisons"] if c["test"] == "block-pyramid"]
    if len(pyramids) != 1:
        check(False, f"one block-pyramid comparison ({len(pyramids)})")
        return None, None, proc.returncode
    return report, pyramids[0], proc.returncode


def main():
    pcbench = sys.argv[1]
    seeds = [1, 2, 3, 4, 5]
    if "--seeds" in sys.argv:
        seeds = [int(s) for s in sys.argv[sys.argv.index("--seeds") + 1].split(",")]
    expected = -SEVERITY / (1.0 + SEVERITY) * NEXT_EVENT_SHARE
    with tempfile.TemporaryDirectory() as root:
        for seed in seeds:
            folder = os.path.join(root, f"seed{seed}")
            report, pyramid, status = verify(pcbench, folder, seed)
            if report is None:
                continue
            tiles, image = pyramid["scales"][0], pyramid["scales"][-1]
            relative, stderr, p = whole_image_welch(folder, report, CONTROL, PARTNER)
            check(status == 0 and pyramid["result"] == "biased" and
                  pyramid["coarsest_differing_block"] == image["block"],
                  f"seed {seed}: verify exits {status}, the pyramid flags it (adjusted p "
                  f"{pyramid['p_adjusted']:.3g}) and the coarsest scale that differs is the "
                  f"whole image ({pyramid['coarsest_differing_block']} px)")
            check(tiles["block"] == 8 and not tiles["blocks_differing"] and
                  tiles["relative_mdb"] > abs(relative),
                  f"seed {seed}: the 8x8 tiles miss it: {len(tiles['blocks_differing'])} blocks "
                  f"differ (adjusted p {tiles['min_p_adjusted']:.3g}), detectable bias "
                  f"{tiles['relative_mdb']:.1%} > |bias| {abs(relative):.2%}")
            weight = len(pyramid["scales"]) * image["tests"]
            decides = image["min_p_adjusted"] == pyramid["p_value"]
            check(p < image["alpha_share"] and
                  (not decides or abs(p * weight / image["min_p_adjusted"] - 1.0) < 0.01),
                  f"seed {seed}: Welch on the replicates' image means: p = {p:.3g} < the image "
                  f"scale's share {image['alpha_share']:.3g}" +
                  (f"; x {weight} = {p * weight:.3g}, the pyramid's {image['min_p_adjusted']:.3g}"
                   if decides else ""))
            check(abs(relative - expected) < 4 * stderr,
                  f"seed {seed}: image bias {relative:+.3%} ± {stderr:.3%}, derived "
                  f"{expected:+.3%}")
        folder = os.path.join(root, "severity0")
        report, pyramid, status = verify(pcbench, folder, seeds[0], severity=0)
        if report is not None:
            relative, stderr, p = whole_image_welch(folder, report, CONTROL, PARTNER)
            check(status == 1 and pyramid["result"] == "consistent" and
                  not any(s["blocks_differing"] for s in pyramid["scales"]),
                  f"severity 0: no scale differs (adjusted p {pyramid['p_adjusted']:.3g}; "
                  f"verify exits {status}: the control missed)")
            check(p > ALPHA, f"severity 0: the whole image consistent: difference "
                  f"{relative:+.3%} ± {stderr:.3%}, Welch p = {p:.3g} > {ALPHA}")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
