#!/usr/bin/python3
"""An interrupted and resumed suite gives the same report as an uninterrupted one.

Usage (ctest test `cli.resume`):
    /usr/bin/python3 tests/resume_test.py PATH/TO/pcbench SOURCE_DIR

Runs one `verify` suite three ways: uninterrupted; stopped by Ctrl-C (SIGINT) during its slow
run and resumed with --resume; killed with SIGKILL as the same run starts and resumed. The suite
has ok, invalid, scene and escalated runs before the slow run (restored on resume) and runs
after it (run on resume), pairwise and tile comparisons, so one Holm family spans restored and
new runs. The
reports must agree in every field but the timings and the context; the scene images
byte for byte. Also: bad input around --resume exits 2 and writes nothing. Prints one line per
check and ends with "N passed, M failed".
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile

import jsonschema
from jsonschema import validators

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402
from report_diff import differences, same_images  # noqa: E402

SUITE = {
    "name": "resume-check", "compare": "pairwise",
    "defaults": {"samples": 20000, "replicates": 8, "seed": 3},
    "runs": [
        {"estimator": "plain", "integrand": "genz-gaussian"},
        {"estimator": "pcbpt", "integrand": "genz-gaussian", "params": {"M": 8}},
        {"estimator": "plain", "integrand": "expr", "params": {"f": "sqrt(x0 - 0.001)"}},
        {"estimator": "plain", "integrand": "furnace", "params": {"resolution": 8},
         "samples": 16, "replicates": 8},
        {"estimator": "pt", "integrand": "furnace", "params": {"resolution": 8},
         "samples": 16, "replicates": 8},
        # Too few effective samples: escalated (4x, 16x) after the first stage of every run,
        # from its restored first stage when resumed.
        {"estimator": "plain", "integrand": "narrow-peak", "samples": 5000},
        # The slow run the signals arrive in (about a second on 2 cores).
        {"estimator": "plain", "integrand": "genz-oscillatory", "samples": 1500000},
        {"estimator": "lvc", "integrand": "genz-gaussian"},
        {"estimator": "vc-all", "integrand": "expr", "params": {"f": "x0*y0"}},
        {"estimator": "plain", "integrand": "expr", "params": {"f": "x0*y0"}},
    ],
}
# Progress prints a line per finished run ("[6/10] plain × narrow-peak · ...: ok, ..."): the
# slow run starts as the run before it finishes.
BEFORE_SLOW = "plain × narrow-peak"
RESTORED = 6  # the runs before the slow one



def run(binary, args, cwd):
    proc = subprocess.run([binary] + args, cwd=cwd, capture_output=True, encoding="utf-8",
                          timeout=300)
    return proc.returncode, proc.stderr


def stop_during_slow_run(binary, args, cwd, sig):
    """Starts pcbench and sends `sig` as the slow run starts; returns the exit status."""
    proc = subprocess.Popen([binary] + args, cwd=cwd, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, encoding="utf-8")
    for line in proc.stderr:
        if line.startswith("[%d/" % RESTORED) and BEFORE_SLOW in line:
            proc.send_signal(sig)
            break
    proc.communicate(timeout=300)
    return proc.returncode


def files_with_times(folder):
    out = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            out[os.path.relpath(path, folder)] = os.stat(path).st_mtime_ns
    return out


def main():
    binary = os.path.abspath(sys.argv[1])
    with open(os.path.join(sys.argv[2], "results", "report.schema.json"), encoding="utf-8") as f:
        schema = json.load(f)
    validator = validators.validator_for(schema)(schema)
    with tempfile.TemporaryDirectory(prefix="pcbench-resume-") as tmp:
        with open(os.path.join(tmp, "suite.json"), "w", encoding="utf-8") as f:
            json.dump(SUITE, f)
        command = ["verify", "suite.json", "-t", "2"]

        status, _ = run(binary, command + ["--out", "full"], tmp)
        check(status == 3, "uninterrupted: exit 3 (one run has non-finite samples)", str(status))
        full_status = status
        with open(os.path.join(tmp, "full", "report.json"), encoding="utf-8") as f:
            full = json.load(f)
        stages = [len(r["escalation"]) for r in full["runs"] if r["integrand"] == "narrow-peak"]
        check(stages == [2], "uninterrupted: narrow-peak escalated twice", str(stages))
        check(not os.path.exists(os.path.join(tmp, "full", "checkpoint")),
              "a finished session removes its checkpoints")

        for name, sig in (("sigint", signal.SIGINT), ("sigkill", signal.SIGKILL)):
            out = ["--out", name]
            status = stop_during_slow_run(binary, command + out, tmp, sig)
            check(status == (130 if sig == signal.SIGINT else -signal.SIGKILL),
                  "%s: stopped as the slow run starts (exit %s)" % (name, status))
            saved = [n for n in os.listdir(os.path.join(tmp, name, "checkpoint"))
                     if n != "session.json" and n.endswith(".json")]
            check(len(saved) == RESTORED, "%s: the %d runs before it are saved" % (name, RESTORED),
                  str(saved))
            if name == "sigkill":
                # Bad input leaves the folder as it was: another seed, another budget, no --out.
                before = files_with_times(os.path.join(tmp, name))
                status, err = run(binary, command + out + ["--resume", "--seed", "4"], tmp)
                check(status == 2 and "session.json" in err and "seed 3" in err,
                      "%s: --resume with another seed is bad input naming the file" % name, err)
                status, err = run(binary, command + out + ["--resume", "-n", "30000"], tmp)
                check(status == 2 and "planned 10 runs" in err,
                      "%s: --resume with another budget is bad input" % name, err)
                status, err = run(binary, command + ["--resume"], tmp)
                check(status == 2 and "--out" in err, "--resume without --out is bad input", err)
                check(files_with_times(os.path.join(tmp, name)) == before,
                      "%s: bad input wrote nothing" % name)
            status, err = run(binary, command + out + ["--resume"], tmp)
            check(status == full_status, "%s: resumed: exit %d as uninterrupted" % (name, status),
                  err)
            check(err.count(": restored from %s/checkpoint/" % name) == RESTORED,
                  "%s: %d runs restored" % (name, RESTORED), err)
            with open(os.path.join(tmp, name, "report.json"), encoding="utf-8") as f:
                resumed = json.load(f)
            errors = sorted(validator.iter_errors(resumed), key=lambda e: list(e.path))
            check(not errors, "%s: the resumed report validates" % name,
                  errors[0].message if errors else "")
            check(resumed["context"].get("resumed") == {"restored_runs": RESTORED},
                  "%s: context.resumed counts the restored runs" % name,
                  str(resumed["context"].get("resumed")))
            diff = differences({k: v for k, v in full.items() if k != "context"},
                               {k: v for k, v in resumed.items() if k != "context"})
            check(not diff, "%s: same report as uninterrupted but timings and context" % name,
                  "; ".join(diff[:5]))
            check(same_images(os.path.join(tmp, "full"), os.path.join(tmp, name)),
                  "%s: the same image files" % name)

        status, err = run(binary, command + ["--out", "full", "--resume"], tmp)
        check(status == 2 and "no interrupted session" in err,
              "--resume of a finished session is bad input", err)
    return summary()


if __name__ == "__main__":
    sys.exit(main())
