#!/usr/bin/python3
"""Runs the default suite and checks what issue 3 asks of it: every row's verdict matches its
expectation (exit status 0), and every finite-variance row could detect a bias of 1% of the
integral of |f| (minimum detectable bias at 80% power, Bonferroni share). Label: full (minutes).

usage: default_suite_check.py PCBENCH SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import time

MAX_DETECTABLE_SHARE = 0.01


def main():
    binary, source = sys.argv[1], sys.argv[2]
    listing = json.loads(subprocess.run([binary, "list", "--json"], check=True,
                                        capture_output=True, text=True).stdout)
    infinite_variance = {i["name"] for i in listing["integrands"]
                         if "infinite-variance" in i.get("tags", [])}
    passed = failed = 0

    def check(ok, what):
        nonlocal passed, failed
        print(("ok      " if ok else "FAILED  ") + what)
        passed += ok
        failed += not ok

    with tempfile.TemporaryDirectory() as out:
        start = time.monotonic()
        status = subprocess.run([binary, "run", os.path.join(source, "suites/default.json"),
                                 "--out", out, "--quiet"]).returncode
        seconds = time.monotonic() - start
        check(status == 0, "default suite exits 0 (got %d) in %.0f s" % (status, seconds))
        report = json.load(open(os.path.join(out, "report.json")))
    for run in report["runs"]:
        name = "%s × %s %s" % (run["estimator"], run["integrand"], run["id"])
        verdict = run["verdict"]
        if verdict is None or run["integrand"] in infinite_variance:
            continue
        share = verdict["min_detectable_bias_vs_mean_abs"]
        check(share is not None and share <= MAX_DETECTABLE_SHARE,
              "%s: detectable bias %.3g%% of mean |f|" % (name, 100 * (share or float("nan"))))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
