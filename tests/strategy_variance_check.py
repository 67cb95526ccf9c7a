#!/usr/bin/python3
"""scripts/strategy_variance.py against an independent computation (ctest `scripts.strategy-variance`).

Usage: /usr/bin/python3 tests/strategy_variance_check.py PATH/TO/pcbench SOURCE_DIR

Renders plain and pcbpt on cornell at 8x8 with --strategy-images under three seeds, runs the
script on the three folders and checks, per run, that the total it prints is the relative
variance of the run's mean image (images/<id>_mean.exr, which the layers sum to) across the
seeds, computed here from the mean images alone with the script's documented scale; and that it
lists the requested number of strategies per run, each with a finite, non-negative variance (a
strategy's variance may exceed the total: under MIS the strategies of one run are correlated).
"""

import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402

SEEDS = ["1", "2", "3"]


def read_rgb(path):
    image = oiio.ImageInput.open(path)
    pixels = image.read_image(format="float")
    image.close()
    return pixels[:, :, :3].astype(np.float64)


def main():
    binary, source = sys.argv[1:3]
    script = os.path.join(source, "scripts", "strategy_variance.py")
    with tempfile.TemporaryDirectory() as scratch:
        folders = []
        for seed in SEEDS:
            out = os.path.join(scratch, "s" + seed)
            subprocess.run([binary, "run", "-e", "plain,pcbpt", "-i", "cornell", "-p",
                            "resolution=8", "-n", "2", "-r", "2", "--strategy-images", "--seed",
                            seed, "--quiet", "--out", out], check=True, capture_output=True)
            folders.append(out)
        done = subprocess.run([sys.executable, script, "--top", "3"] + folders,
                              capture_output=True, text=True)
        check(done.returncode == 0, "the script exits 0", done.stderr)
        printed = dict(re.findall(r"^(\w[^:]*): relative variance of the run's mean (\S+)",
                                  done.stdout, re.M))
        check(len(printed) == 2, "one total per run", done.stdout)
        # The same figure from the mean images alone.
        means = {}
        for folder in folders:
            for run in json.load(open(os.path.join(folder, "report.json")))["runs"]:
                params = " ".join(f"{k}={v}" for k, v in run["params"].items()
                                  if k != "resolution")
                label = f"{run['estimator']} on {run['integrand']} {params}"
                means.setdefault(label, []).append(
                    read_rgb(os.path.join(folder, run["image"]["files"]["mean"])))
        pooled = [m for ms in means.values() for m in ms]
        scale = np.mean(pooled, 0) + 0.01 * np.mean(pooled)
        for label, ms in means.items():
            expected = np.mean(np.var(np.stack(ms), 0, ddof=1) / scale**2)
            got = float(printed.get(label, "nan"))
            # The EXR layers are 32-bit floats: their sum meets the mean image to about 1e-6.
            check(abs(got - expected) <= 1e-3 * expected,
                  f"{label.split(' on ')[0]}: total {got:.4g} is the variance of the mean "
                  f"images {expected:.4g}")
        layers = re.findall(r"^  (s\d+_t\d+) +variance +(\S+)", done.stdout, re.M)
        check(len(layers) == 6, "three strategies listed per run", done.stdout)
        check(all(np.isfinite(float(v)) and float(v) >= 0.0 for _, v in layers),
              "every listed variance is finite and non-negative")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
