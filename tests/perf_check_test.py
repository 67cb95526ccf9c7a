#!/usr/bin/python3
"""The regression check flags an injected slowdown and nothing else (ctest perf.check).

usage: perf_check_test.py SOURCE_DIR
Compares the committed baseline with itself (nothing flagged, exit 0), with a copy where one
benchmark is 1.5x slower (exactly that one flagged, exit 1), with a copy where every
benchmark is 5% slower (within the floor: exit 0), and with a copy where one ray-rate ratio is
1.5x lower (exactly that one flagged).
"""
import copy
import json
import os
import subprocess
import sys
import tempfile


def main():
    source = sys.argv[1]
    baseline = os.path.join(source, "results", "baseline", "bench.json")
    script = os.path.join(source, "scripts", "check-perf.py")
    with open(baseline, encoding="utf-8") as f:
        report = json.load(f)
    names = sorted({b["run_name"] for b in report["benchmarks"] if b.get("run_type") == "aggregate"})
    victim = names[len(names) // 2]
    failures = 0

    def run(doctored, expected_status, must_name=None, what=""):
        nonlocal failures
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump(doctored, f)
            path = f.name
        result = subprocess.run([sys.executable, script, baseline, path], capture_output=True,
                                text=True)
        os.unlink(path)
        ok = result.returncode == expected_status
        slower = [line.split()[0] for line in result.stdout.splitlines() if "SLOWER" in line]
        if must_name is not None:
            ok = ok and slower == [must_name]
        print(("ok      " if ok else "FAILED  ") + what + " (exit %d, flagged %s)"
              % (result.returncode, slower))
        failures += not ok

    def scaled(factor, only=None):
        doctored = copy.deepcopy(report)
        for b in doctored["benchmarks"]:
            if only is None or b["run_name"] == only:
                for key in ("cpu_time", "real_time"):
                    if b.get("aggregate_name") not in ("cv",):
                        b[key] = b[key] * factor
        return doctored

    run(report, 0, what="the baseline against itself: nothing flagged")
    run(scaled(1.5, victim), 1, victim, what="%s made 1.5x slower: flagged alone" % victim)
    run(scaled(1.05), 0, what="everything 5% slower: within the floor, not flagged")
    # The ray-rate ratio whose own noise allows the least: a 1.5x drop must exceed its margin
    # (max(15%, 4 x twice its cv)), or the check could not be asked to flag it.
    ratio_cv = {b["run_name"]: b["ratio"] for b in report["benchmarks"]
                if b.get("aggregate_name") == "cv" and "ratio" in b}
    if ratio_cv:
        name = min(ratio_cv, key=ratio_cv.get)
        if 1.5 <= 1.0 + max(0.15, 8.0 * ratio_cv[name]):
            print("FAILED  no ray-rate ratio in the baseline is steady enough to test (cv %.3f)"
                  % ratio_cv[name])
            failures += 1
        doctored = copy.deepcopy(report)
        for b in doctored["benchmarks"]:
            if b["run_name"] == name and b.get("aggregate_name") != "cv":
                b["ratio"] = b["ratio"] / 1.5
        run(doctored, 1, name, what="%s's ray-rate ratio 1.5x lower: flagged alone" % name)
    print("%d failed" % failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
