#!/usr/bin/python3
"""The worked example of docs/dev/extending.md "Adding a scene estimator" (ctest `examples.nee`,
label ci).

Usage:
    /usr/bin/python3 tests/example_estimator_check.py PATH/TO/pcbench_examples PATH/TO/pcbench

Runs `pcbench_examples verify -e example-nee,pt -i furnace,cornell` and checks:
  - exit 0: every verdict as expected;
  - example-nee was tested against the furnace's exact image per 8x8 tile and found consistent;
  - it was compared with pt per tile on cornell and found consistent, and the verifier's own
    check (2x the detectable bias put into one tile) flagged that comparison's injected copy;
  - `pcbench list` does not name it (it is registered in pcbench_examples only) and
    `pcbench_examples list` does.
Prints one line per check; exits 1 if any failed.
"""

import json
import os
import subprocess
import sys
import tempfile


def main():
    examples, pcbench = sys.argv[1:3]
    failed = 0

    def check(ok, what):
        nonlocal failed
        print(("ok      " if ok else "FAILED  ") + what)
        failed += not ok

    with tempfile.TemporaryDirectory(prefix="pcbench-example-") as out:
        status = subprocess.run(
            [examples, "verify", "-e", "example-nee,pt", "-i", "furnace,cornell", "-p",
             "resolution=32", "-n", "16", "-r", "8", "-q", "--out", out,
             "--reference-cache", os.path.join(out, "no-cache")]).returncode
        check(status == 0, f"pcbench_examples verify exits 0 (got {status})")
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
    comparisons = report.get("comparisons", [])

    def found(integrand, estimator, result):
        return any(c["integrand"] == integrand and c["estimator"].startswith(estimator)
                   and c["result"] == result for c in comparisons)

    check(found("furnace", "example-nee vs exact", "consistent"),
          "example-nee is consistent with the exact furnace per tile")
    check(found("cornell", "example-nee vs pt", "consistent"),
          "example-nee is consistent with pt per tile on cornell")
    check(any(c["integrand"] == "cornell" and c["estimator"].startswith("example-nee vs pt (")
              and c["result"] == "biased" for c in comparisons),
          "the injected 2xMDB copy of that comparison is flagged")
    listed = subprocess.run([pcbench, "list"], capture_output=True, text=True).stdout
    check("example-nee" not in listed, "pcbench list does not name example-nee")
    listed = subprocess.run([examples, "list"], capture_output=True, text=True).stdout
    check("example-nee" in listed, "pcbench_examples list names it")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
