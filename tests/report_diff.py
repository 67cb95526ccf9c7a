"""Comparing two reports of the same work: every field but the timings, and the image files.

Shared by the tests that show a report is the same however it was made (tests/resume_test.py:
interrupted and resumed; tests/mpi_check.py: over MPI ranks or shards).
"""

import json
import os

TIMING = {"seconds", "cpu_seconds", "wall_seconds", "seconds_per_sample", "efficiency",
          "efficiency_low", "efficiency_high", "pilot_cpu_seconds_per_sample",
          "rays_per_cpu_second", "cpu_seconds_per_replicate", "rel_mse_at_1_cpu_second"}
# An efficiency ratio's cost factor, and with it the ratio, is measured time too (its variance
# factor is not).
RATIO_TIMING = {"ratio", "low", "high", "cost_ratio", "cost_low", "cost_high"}


def differences(a, b, path="", out=None):
    out = [] if out is None else out
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if key in TIMING or (path.startswith("/efficiency_ratios/") and key in RATIO_TIMING):
                continue
            if key not in a or key not in b:
                out.append("%s/%s only in one report" % (path, key))
            else:
                differences(a[key], b[key], "%s/%s" % (path, key), out)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            differences(x, y, "%s/%d" % (path, i), out)
    elif a != b:
        out.append("%s: %s vs %s" % (path, json.dumps(a)[:80], json.dumps(b)[:80]))
    return out


def same_images(a, b):
    names = sorted(os.listdir(os.path.join(a, "images")))
    return names == sorted(os.listdir(os.path.join(b, "images"))) and all(
        open(os.path.join(a, "images", n), "rb").read()
        == open(os.path.join(b, "images", n), "rb").read() for n in names)
