#!/usr/bin/python3
"""The include directions of the tree, so that the layering cannot rot silently.

Usage (ctest `layers.includes`, label ci): /usr/bin/python3 tests/include_layers_check.py SOURCE_DIR

From the bottom up (docs/ARCHITECTURE.md):
  base/       params, rng, errors, nearest_name, text_hash, child_process: base only
  results/    image files and the report: base and results/ only
  integrands/ analytic integrands, scenes and the renderer's services: base, results/ and
              integrands/ only (never estimators/: an estimator is not part of a scene)
  estimators/ analytic and scene estimators: base, results/, integrands/, estimators/
  harness/    planning, running, statistics, commands: anything below
  examples/, benchmarks/, tests/, fuzz/: anything
KNOWN_DEBTS lists the includes that break this today, each with the issue that removes it: a new
one fails the test, and a debt paid off must be struck from the list (the test fails on a stale
entry too, so the list stays true).
"""

import os
import re
import sys

# (file, included header): upward includes that exist today, each with the issue that removes it.
KNOWN_DEBTS = set()
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def allowed(path, header):
    layer = path.split("/")[0]
    top = header.split("/")[0]
    if layer == "base":
        return top == "base"
    if top == "base":
        return True
    if layer == "results":
        return top == "results"
    if layer == "integrands":
        return top in ("integrands", "results")
    if layer == "estimators":
        return top in ("results", "integrands", "estimators")
    return True  # harness/ and the programs may include anything below them


def main():
    source = sys.argv[1]
    failures, seen_debts, checked = [], set(), 0
    for folder in ("base", "harness", "results", "integrands", "estimators"):
        for root, _, files in os.walk(os.path.join(source, folder)):
            for name in files:
                if not name.endswith((".h", ".cpp")):
                    continue
                path = os.path.relpath(os.path.join(root, name), source)
                with open(os.path.join(source, path), encoding="utf-8") as f:
                    for line in f:
                        match = INCLUDE.match(line)
                        if not match:
                            continue
                        header = match.group(1)
                        if "/" not in header:
                            continue  # a generated header beside the file
                        checked += 1
                        if allowed(path, header):
                            continue
                        if (path, header) in KNOWN_DEBTS:
                            seen_debts.add((path, header))
                            continue
                        failures.append(f"{path} includes {header}: an upward include")
    for path, header in sorted(KNOWN_DEBTS - seen_debts):
        failures.append(f"KNOWN_DEBTS lists {path} -> {header}, which is gone: strike it")
    for failure in failures:
        print("FAIL " + failure)
    print(f"{checked} includes checked, {len(seen_debts)} known debts")
    print(f"{1 if not failures else 0} passed, {1 if failures else 0} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
