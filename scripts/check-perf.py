#!/usr/bin/python3
"""Compares a Google Benchmark JSON report with the committed baseline and flags slowdowns beyond
run-to-run noise.

usage: check-perf.py BASELINE.json NEW.json

Both files come from `pcbench_bench --benchmark_repetitions=N --benchmark_format=json` (N >= 3).
For every benchmark in both, the medians of CPU time are compared. A benchmark is flagged when
    new_median > baseline_median * (1 + max(MIN_SLOWDOWN, NOISE_FACTOR * (cv_baseline + cv_new)))
with cv the coefficient of variation across repetitions: a slowdown must exceed both a floor and
several times the noise both runs showed. Benchmarks with a `ratio` counter (BM_RayRate: a
render's rays per second over Embree's alone on the same rays) are also flagged when the median
ratio falls below the baseline's by the same kind of margin, from the ratios' own coefficients of
variation. Prints one line per benchmark; exits 1 when any is
flagged, 2 on bad input.
"""
import json
import sys

MIN_SLOWDOWN = 0.15
NOISE_FACTOR = 4.0


def aggregates(path):
    try:
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        print("check-perf: %s: %s" % (path, e))
        sys.exit(2)
    out = {}
    for b in report.get("benchmarks", []):
        if b.get("run_type") != "aggregate":
            continue
        entry = out.setdefault(b["run_name"], {})
        entry[b["aggregate_name"]] = b
    usable = {name: e for name, e in out.items() if "median" in e and "cv" in e}
    if not usable:
        print("check-perf: %s holds no median/cv aggregates (run with --benchmark_repetitions=3 "
              "or more)" % path)
        sys.exit(2)
    return usable


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    base = aggregates(sys.argv[1])
    new = aggregates(sys.argv[2])
    flagged = []
    print("%-60s %12s %12s %8s %8s" % ("benchmark", "baseline", "new", "ratio", "allowed"))
    for name in sorted(set(base) & set(new)):
        b, n = base[name], new[name]
        ratio = n["median"]["cpu_time"] / b["median"]["cpu_time"]
        noise = NOISE_FACTOR * (b["cv"]["cpu_time"] + n["cv"]["cpu_time"])
        allowed = 1.0 + max(MIN_SLOWDOWN, noise)
        slow = ratio > allowed
        if "ratio" in b["median"] and "ratio" in n["median"]:
            ratio_noise = NOISE_FACTOR * (b["cv"].get("ratio", 0.0) + n["cv"].get("ratio", 0.0))
            ratio_allowed = 1.0 + max(MIN_SLOWDOWN, ratio_noise)
            slow = slow or n["median"]["ratio"] * ratio_allowed < b["median"]["ratio"]
        if slow:
            flagged.append(name)
        print("%-60s %12.4g %12.4g %8.3f %8.3f%s" % (name, b["median"]["cpu_time"],
                                                   n["median"]["cpu_time"], ratio, allowed,
                                                   "  SLOWER" if slow else ""))
    for name in sorted(set(base) - set(new)):
        print("%-60s only in the baseline" % name)
    print("%d slower beyond noise%s" % (len(flagged), (": " + ", ".join(flagged)) if flagged else ""))
    return 1 if flagged else 0


if __name__ == "__main__":
    sys.exit(main())
