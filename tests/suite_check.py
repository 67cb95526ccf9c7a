#!/usr/bin/python3
"""Runs a shipped suite and checks what its issue asks of it: every row's verdict matches its
expectation (exit status 0) and, unless --no-power, every finite-variance row could detect a bias
of 1% of the integral of |f| (minimum detectable bias at 80% power, Bonferroni share). For the
proof suite (`verify`), every negative control of the registry must be a row, come out biased,
and no honest row may be flagged.

usage: suite_check.py PCBENCH SOURCE_DIR SUITE COMMAND [--no-power] [pcbench options...]
  COMMAND is run or verify; e.g. suite_check.py build/release/pcbench . suites/proof.json verify
"""
import json
import os
import subprocess
import sys
import tempfile
import time

MAX_DETECTABLE_SHARE = 0.01


def main():
    binary, source, suite, command = sys.argv[1:5]
    extra = sys.argv[5:]
    check_power = "--no-power" not in extra
    extra = [a for a in extra if a != "--no-power"]
    listing = json.loads(subprocess.run([binary, "list", "--json"], check=True,
                                        capture_output=True, text=True).stdout)
    infinite_variance = {i["name"] for i in listing["integrands"]
                         if "infinite-variance" in i.get("tags", [])}
    # The analytic negative controls (the scene controls run on scenes, not in these suites).
    controls = {e["name"] for e in listing["estimators"] if e["biased"] and e["analytic"]}
    passed = failed = 0

    def check(ok, what):
        nonlocal passed, failed
        print(("ok      " if ok else "FAILED  ") + what)
        passed += ok
        failed += not ok

    with tempfile.TemporaryDirectory() as out:
        start = time.monotonic()
        args = [binary, command, os.path.join(source, suite), "--out", out, "--quiet"] + extra
        status = subprocess.run(args).returncode
        seconds = time.monotonic() - start
        check(status == 0, "%s exits 0 (got %d) in %.0f s" % (" ".join(args[1:3] + extra),
                                                             status, seconds))
        report = json.load(open(os.path.join(out, "report.json")))
    for run in report["runs"]:
        name = "%s × %s %s" % (run["estimator"], run["integrand"], run["id"])
        verdict = run["verdict"]
        check(verdict is not None and verdict["result"] == verdict["expect"],
              "%s: %s (expected %s)" % (name, verdict and verdict["result"],
                                        verdict and verdict["expect"]))
        if verdict is None or run["integrand"] in infinite_variance or not check_power:
            continue
        share = verdict["min_detectable_bias_vs_mean_abs"]
        check(share is not None and share <= MAX_DETECTABLE_SHARE,
              "%s: detectable bias %.3g%% of mean |f|" % (name, 100 * (share or float("nan"))))
    if command == "verify":
        flagged = {r["estimator"] for r in report["runs"]
                   if r["verdict"] and r["verdict"]["result"] == "biased"}
        check(flagged == controls, "exactly the negative controls are flagged: %s"
              % ", ".join(sorted(flagged)))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
