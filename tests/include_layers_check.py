#!/usr/bin/python3
"""The include directions of the tree, so that the layering cannot rot silently.

Usage (ctest `layers.includes`, label ci): /usr/bin/python3 tests/include_layers_check.py SOURCE_DIR

The layers from the bottom up (docs/dev/ARCHITECTURE.md); a file may include headers of its own
layer and of the layers below it, never one above:
  base/              params, rng, errors, nearest_name, text_hash, atomic_file, json_input, ...
  results/           image files, EXR, the build context
  integrands/        analytic integrands, scenes and the renderer's services (never estimators/:
                     an estimator is not part of a scene)
  estimators/        analytic and scene estimators, the registry
  harness/plan/      input and planning: suite files, estimates files, image sets, plans
  harness/run/       running: runner, scene runner, tallies, equal time, resume journal, replay
  harness/verify/    statistics and verification, and the run records they make
  harness/session/   a session: runs, tests and publishes its report
  harness/commands/  the command line and one file per command
examples/, benchmarks/, tests/, fuzz/ and python/ are programs and may include anything.
So no header of estimators/, integrands/ or results/ includes one from the harness's running or
command layers, and a file directly in harness/ (outside a layer folder) is refused too.

Before the tree, the check runs on two small made-up trees: one with a single upward include
(harness/run/ including harness/commands/), which it must refuse, and the same tree with that
include pointing down, which it must accept; so a check that passes everything fails the test.
"""

import os
import re
import sys
import tempfile

LAYERS = ["base", "results", "integrands", "estimators", "harness/plan", "harness/run",
          "harness/verify", "harness/session", "harness/commands"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def layer_of(path):
    """The index of the layer `path` belongs to; None outside the layers (programs); -1 for a
    file directly in harness/ or in an unknown harness/ folder."""
    for index in reversed(range(len(LAYERS))):
        if path.startswith(LAYERS[index] + "/"):
            return index
    return -1 if path.startswith("harness/") else None


def check(source):
    failures, checked = [], 0
    for folder in ("base", "harness", "results", "integrands", "estimators"):
        for root, _, files in os.walk(os.path.join(source, folder)):
            for name in files:
                if not name.endswith((".h", ".cpp")):
                    continue
                path = os.path.relpath(os.path.join(root, name), source)
                own = layer_of(path)
                if own == -1:
                    failures.append(f"{path} is in harness/ but in none of its layer folders")
                    continue
                with open(os.path.join(source, path), encoding="utf-8") as f:
                    for line in f:
                        match = INCLUDE.match(line)
                        if not match or "/" not in match.group(1):
                            continue  # a system header, or a generated one beside the file
                        header = match.group(1)
                        checked += 1
                        theirs = layer_of(header)
                        if theirs is None or theirs == -1:
                            failures.append(f"{path} includes {header}, which is in no layer")
                        elif theirs > own:
                            failures.append(f"{path} ({LAYERS[own]}) includes {header} "
                                            f"({LAYERS[theirs]}): an upward include")
    return failures, checked


def self_test():
    """The check refuses an upward include and accepts the same tree with it turned down."""
    problems = []
    for target, expect_fail in (("harness/commands/cli.h", True), ("harness/plan/plan.h", False)):
        with tempfile.TemporaryDirectory() as tree:
            files = {"harness/commands/cli.h": '#include "harness/run/runner.h"\n',
                     "harness/plan/plan.h": '#include "base/params.h"\n',
                     "base/params.h": "#include <string>\n",
                     "harness/run/runner.h": f'#include "{target}"\n'}
            for path, text in files.items():
                os.makedirs(os.path.join(tree, os.path.dirname(path)), exist_ok=True)
                with open(os.path.join(tree, path), "w", encoding="utf-8") as f:
                    f.write(text)
            failures, _ = check(tree)
            if bool(failures) != expect_fail:
                problems.append(f"self-test: harness/run/runner.h including {target} gave "
                                f"{failures or 'no failure'}")
    return problems


def main():
    failures = self_test()
    tree_failures, checked = check(sys.argv[1])
    failures += tree_failures
    for failure in failures:
        print("FAIL " + failure)
    print(f"{checked} includes checked in {len(LAYERS)} layers; the check refuses an upward "
          f"include in its self-test: {'no' if any('self-test' in f for f in failures) else 'yes'}")
    print(f"{1 if not failures else 0} passed, {1 if failures else 0} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
