#!/usr/bin/python3
"""The replay command a run with a non-finite sample prints reproduces that sample.

Usage (ctest test `cli.replay`):
    /usr/bin/python3 tests/replay_command_test.py PATH/TO/pcbench

A run of f = sqrt(x0 - 0.001) (NaN where x0 < 0.001) exits 3; the command in its report's
first_nonfinite.replay (also printed on stderr) is run through the shell as printed, with
`pcbench` standing for the binary: it exits 3 and shows a non-finite estimate at the same
sample, with a pool path at x0 < 0.001. A finite sample replays as the value the run tallied: with one sample
per replicate, a replicate's estimate is its sample 0. Prints one line per check and ends with
"N passed, M failed".
"""

import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402



def run(args, cwd, shell=False):
    proc = subprocess.run(args, cwd=cwd, capture_output=True, encoding="utf-8", timeout=120,
                          shell=shell)
    return proc.returncode, proc.stdout, proc.stderr


def main():
    binary = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="pcbench-replay-") as tmp:
        status, _, err = run([binary, "run", "-e", "pcbpt", "-i", "expr", "-p",
                              "f=sqrt(x0 - 0.001)", "-p", "M=4", "-n", "3000", "-r", "4",
                              "--seed", "5", "--out", "nan"], tmp)
        check(status == 3, "a run with NaN samples exits 3", str(status))
        with open(os.path.join(tmp, "nan", "report.json"), encoding="utf-8") as f:
            first = json.load(f)["runs"][0]["first_nonfinite"]
        command = first.get("replay", "")
        check(command.startswith("pcbench replay ") and command in err,
              "the report and stderr carry the replay command", command)
        shell_command = binary + command[len("pcbench"):]
        status, out, err = run(shell_command, tmp, shell=True)
        check(status == 3 and ("estimate: -nan" in out or "estimate: nan" in out),
              "the command, run as printed, replays a non-finite estimate (exit 3)",
              "%s %s %s" % (status, out, err))
        status, out, err = run(shell_command + " --json", tmp, shell=True)
        replayed = json.loads(out) if status in (0, 3) else {}
        check(replayed.get("estimate") == "nan" and replayed.get("sample") == first["sample"]
              and replayed.get("replicate") == first["replicate"],
              "at the same replicate and sample", out[:200] + err)
        pool = [x["coordinates"][0] for x in replayed.get("pool", [])]
        check(len(pool) == 4 and any(x < 0.001 for x in pool),
              "its pool of 4 holds a light path where f is NaN (x0 < 0.001)", str(pool))

        status, _, err = run([binary, "run", "-e", "pcbpt", "-i", "genz-gaussian", "-p",
                              "pool=shared", "-n", "1", "-r", "3", "--out", "one"], tmp)
        with open(os.path.join(tmp, "one", "report.json"), encoding="utf-8") as f:
            tallied = [r["estimate"] for r in json.load(f)["runs"][0]["replicates"]]
        values = []
        for r in range(3):
            status, out, err = run([binary, "replay", "-e", "pcbpt", "-i", "genz-gaussian", "-p",
                                    "pool=shared", "-n", "1", "-r", "3", "--replicate", str(r),
                                    "--sample", "0", "--json"], tmp)
            values.append(json.loads(out)["estimate"] if status == 0 else err)
        check(values == tallied, "finite samples replay as the values the run tallied",
              "%s vs %s" % (values, tallied))
    return summary()


if __name__ == "__main__":
    sys.exit(main())
