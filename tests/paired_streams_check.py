#!/usr/bin/python3
"""The paired design (issue 25, item 7): runs that share their random streams, compared on
replicate differences.

Usage:
    /usr/bin/python3 tests/paired_streams_check.py PATH/TO/pcbench

ctl-scene-nee-count at severity 0.002 is pt with its next-event estimates divided by 1.002: the
image is low by about 0.2%. On cornell at 64x64, 1 spp x 16 replicates, the check runs pt against
it twice, `pcbench run ... --replicate-images` with and without --paired, and reads the reports:
  - paired: both runs say "streams": "paired", their pyramid says "paired": true and flags the
    control (run exits 0), with a whole-image detectable bias below the bias;
  - apart from pcbench's code, the replicates' whole-image channel means are correlated between
    the runs (the same camera paths), and the paired t on their differences is below the image
    scale's share of alpha; where the image scale decides, its p times the pyramid's weight
    (L scales x 3 channels) is the comparison's adjusted p;
  - unpaired: the pyramid is Welch's ("paired": false, "streams": "own"), its whole-image
    detectable bias exceeds the bias, and it misses the control (run exits 1);
  - the paired ids differ from the unpaired ones (a journal never mixes them).
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

BASE = "pt"
CONTROL = "ctl-scene-nee-count"
SEVERITY = 0.002


def run(pcbench, folder, paired):
    """The report, its pyramid comparison and the run's exit status."""
    args = [pcbench, "run", "-e", f"{BASE},{CONTROL}", "-i", "cornell", "-p", "resolution=64",
            "-p", f"severity={SEVERITY}", "-n", "1", "-r", "16", "--replicate-images", "-q",
            "--out", folder] + (["--paired"] if paired else [])
    proc = subprocess.run(args, capture_output=True, text=True)
    path = os.path.join(folder, "report.json")
    if not os.path.exists(path):
        sys.exit(f"paired_streams_check: no report (exit {proc.returncode}): {proc.stderr[-300:]}")
    with open(path) as f:
        report = json.load(f)
    pyramids = [c for c in report["comparisons"]
                if c["test"] == "block-pyramid" and not c["a"].endswith("+injected")]
    if len(pyramids) != 1:
        sys.exit(f"paired_streams_check: {len(pyramids)} block-pyramid comparisons, not 1")
    return report, pyramids[0], proc.returncode


def paired_whole_image(folder, report):
    """Per channel, the paired t on the whole-image replicate means: (smallest p, smallest
    correlation between the runs' replicate means, relative difference of the channel sums)."""
    runs = {r["estimator"]: r for r in report["runs"]}
    x = replicate_channel_means(folder, runs[CONTROL])
    y = replicate_channel_means(folder, runs[BASE])
    p, correlation = [], []
    for c in range(3):
        d = x[:, c] - y[:, c]
        t = d.mean() / math.sqrt(d.var(ddof=1) / len(d))
        p.append(student_two_sided_p(t, len(d) - 1))
        xc, yc = x[:, c] - x[:, c].mean(), y[:, c] - y[:, c].mean()
        correlation.append((xc * yc).sum() / math.sqrt((xc * xc).sum() * (yc * yc).sum()))
    return min(p), min(correlation), x.sum(1).mean() / y.sum(1).mean() - 1.0


def main():
    pcbench = sys.argv[1]
    with tempfile.TemporaryDirectory() as root:
        paired_folder = os.path.join(root, "paired")
        report, pyramid, status = run(pcbench, paired_folder, paired=True)
        image = pyramid["scales"][-1]
        check(all(r["streams"] == "paired" for r in report["runs"]) and pyramid["paired"],
              "paired: both runs' streams are paired and the pyramid is the paired test")
        p, correlation, relative = paired_whole_image(paired_folder, report)
        check(status == 0 and pyramid["result"] == "biased" and
              image["relative_mdb"] < abs(relative),
              f"paired: run exits {status}, the control flagged (adjusted p "
              f"{pyramid['p_adjusted']:.3g}); whole-image detectable bias "
              f"{image['relative_mdb']:.3%} < |bias| {abs(relative):.3%}")
        check(correlation > 0.9,
              f"paired: the runs' whole-image replicate means correlate ({correlation:.4f} in "
              "the least correlated channel)")
        weight = len(pyramid["scales"]) * image["tests"]
        decides = image["min_p_adjusted"] == pyramid["p_value"]
        check(p < image["alpha_share"] and
              (not decides or abs(p * weight / image["min_p_adjusted"] - 1.0) < 0.01),
              f"paired: the paired t on the replicates' image means: p = {p:.3g} < the image "
              f"scale's share {image['alpha_share']:.3g}" +
              (f"; x {weight} = {p * weight:.3g}, the pyramid's {image['min_p_adjusted']:.3g}"
               if decides else ""))
        paired_ids = {r["id"] for r in report["runs"]}

        report, pyramid, status = run(pcbench, os.path.join(root, "own"), paired=False)
        image = pyramid["scales"][-1]
        check(all(r["streams"] == "own" for r in report["runs"]) and not pyramid["paired"],
              "unpaired: the runs have their own streams and the pyramid is Welch's")
        check(status == 1 and pyramid["result"] == "consistent" and
              image["relative_mdb"] > abs(relative),
              f"unpaired: run exits {status}, the control missed (adjusted p "
              f"{pyramid['p_adjusted']:.3g}); whole-image detectable bias "
              f"{image['relative_mdb']:.3%} > |bias| {abs(relative):.3%}")
        check(not paired_ids & {r["id"] for r in report["runs"]},
              "the paired runs' ids differ from the unpaired ones")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
