#!/usr/bin/env python3
"""A pcbench report as a pandas table: each run's estimate, error and efficiency.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/report_to_table.py [REPORT]

REPORT is a report.json or its folder (results/latest after `pcbench run`); without one, a
small selection (four estimators on `door`, M = 4 and 16) is run first, with no files written.
"""

import sys

import pandas as pd

import pcbench

if len(sys.argv) > 1:
    runs, _ = pcbench.read_report(sys.argv[1])
else:
    runs = pcbench.run(estimators=["plain", "vc-all", "lvc", "pcbpt"], integrands="door",
                       params={"M": [4, 16]}, samples=20000, replicates=8, seed=1).runs

runs["M"] = runs["params"].map(lambda p: p.get("M", ""))
table = runs[["estimator", "integrand", "M", "mean", "stderr", "bias_in_stderr", "rel_mse",
              "cpu_seconds", "efficiency", "verdict"]]
# Efficiency relative to the first plain run on each integrand: the figure papers compare.
plain = runs[runs["estimator"] == "plain"].groupby("integrand")["efficiency"].first()
table = table.assign(vs_plain=runs["efficiency"] / runs["integrand"].map(plain))
with pd.option_context("display.width", 120, "display.float_format", "{:.4g}".format):
    print(table.to_string(index=False))
sys.exit(0 if (runs["verdict"] == "consistent").all() else 1)
