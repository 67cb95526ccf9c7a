#!/usr/bin/python3
"""Shards of a suite, merged, give the report and images one process writes, bit for bit.

Usage (ctest test `cli.shards`):
    /usr/bin/python3 tests/shard_check.py PATH/TO/pcbench PATH/TO/pcbench_exr_pixel_hash

Runs one small `verify` suite (analytic and scene runs, an escalated run, pairwise and tile
comparisons) in one process and as 3 shards (`--shard i/3`, harness/session/shard.h); merging two of
them names the missing one, exits 2 and writes nothing; running it and merging again gives the
one-process report (every field but timings and context) and its images pixel for pixel. Also
bad --shard values and shards of different jobs are bad input. Prints one line per check and
ends with "N passed, M failed".
"""

import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402
from report_diff import differences  # noqa: E402

SUITE = {
    "name": "shard-check", "compare": "pairwise",
    "defaults": {"samples": 4000, "replicates": 7, "seed": 5},
    "runs": [
        {"estimator": "plain", "integrand": "genz-gaussian"},
        {"estimator": "pcbpt", "integrand": "genz-gaussian", "params": {"M": 8}},
        {"estimator": "plain", "integrand": "furnace", "params": {"resolution": 8},
         "samples": 8, "replicates": 5},
        {"estimator": "pt", "integrand": "furnace", "params": {"resolution": 8},
         "samples": 8, "replicates": 5},
        {"estimator": "plain", "integrand": "narrow-peak", "samples": 2000,
         "expect": "inconclusive"},
    ],
}


def run(command, cwd):
    proc = subprocess.run(command, cwd=cwd, capture_output=True, encoding="utf-8", timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


def pixel_hashes(hasher, folder):
    names = sorted(n for n in os.listdir(folder) if n.endswith(".exr"))
    out = subprocess.run([hasher] + names, cwd=folder, capture_output=True, encoding="utf-8",
                         check=True).stdout if names else ""
    return dict(reversed(line.split()) for line in out.splitlines())


def report(folder):
    with open(os.path.join(folder, "report.json"), encoding="utf-8") as f:
        return {k: v for k, v in json.load(f).items() if k != "context"}


def main():
    binary = os.path.abspath(sys.argv[1])
    hasher = os.path.abspath(sys.argv[2])
    with tempfile.TemporaryDirectory(prefix="pcbench-shards-") as tmp:
        with open(os.path.join(tmp, "suite.json"), "w", encoding="utf-8") as f:
            json.dump(SUITE, f)
        command = [binary, "verify", "suite.json", "--quiet"]
        one_status, out = run(command + ["--out", "one"], tmp)
        check(one_status == 0, "one process: exit 0", out)

        for i in (0, 2):
            status, out = run(command + ["--shard", "%d/3" % i, "--out", "s%d" % i], tmp)
            check(status == 0 and ("shard %d/3" % i) in out and
                  not os.path.exists(os.path.join(tmp, "s%d" % i, "report.json")),
                  "shard %d/3: exit 0, runs saved, no report" % i, out)
        status, out = run([binary, "merge", "s0", "s2", "--out", "merged"], tmp)
        check(status == 2 and "missing shard 1/3" in out
              and not os.path.exists(os.path.join(tmp, "merged")),
              "merge without shard 1/3: exit 2 naming it, nothing written", out)
        status, out = run(command + ["--shard", "1/3", "--out", "s1"], tmp)
        check(status == 0, "shard 1/3 run afterwards: exit 0", out)
        status, out = run([binary, "merge", "s2", "s0", "s1", "--out", "merged"], tmp)
        check(status == one_status, "merge of the 3 shards: exit %d as one process" % status, out)
        diff = differences(report(os.path.join(tmp, "one")), report(os.path.join(tmp, "merged")))
        check(not diff, "merged: the report one process writes, but timings", "; ".join(diff[:5]))
        one_images = pixel_hashes(hasher, os.path.join(tmp, "one", "images"))
        check(one_images and one_images == pixel_hashes(hasher,
                                                         os.path.join(tmp, "merged", "images")),
              "merged: the same %d images, pixel for pixel" % len(one_images))

        for bad in ("3/3", "1", "a/2", "0/0"):
            status, out = run(command + ["--shard", bad, "--out", "bad"], tmp)
            check(status == 2 and "--shard" in out and not os.path.exists(os.path.join(tmp, "bad")),
                  "--shard %s: bad input, nothing written" % bad, out)
        status, out = run(command + ["--seed", "6", "--shard", "1/3", "--out", "other"], tmp)
        status, out = run([binary, "merge", "s0", "other", "s2", "--out", "mixed"], tmp)
        check(status == 2 and "another job" in out and not os.path.exists(
            os.path.join(tmp, "mixed")), "merge of shards of two jobs: bad input", out)
    return summary()


if __name__ == "__main__":
    sys.exit(main())
