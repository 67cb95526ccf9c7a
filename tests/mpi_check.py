#!/usr/bin/python3
"""Over MPI ranks, pcbench writes the report and images one process writes, bit for bit.

Usage (ctest tests `mpi.ranks` and `mpi.door_ajar`):
    /usr/bin/python3 tests/mpi_check.py PATH/TO/pcbench PATH/TO/pcbench_exr_pixel_hash [SUITE]

Runs one small `verify` suite (analytic runs with an uneven number of replicates, an invalid
run, scene runs with strategy and replicate images, an escalated run, pairwise and tile
comparisons: one Holm family) in one process and under `mpirun -np 2` and `-np 3
--oversubscribe` (harness/run/replicate_farm.h). The reports must agree in every field but the
timings and the context, the images pixel for pixel. Also: an equal-time run on 3 ranks takes
its budget from rank 0's pilot, and that budget as --samples in one process gives its numbers; `pcbench reference` over 2 ranks stores
the image one process stores; bad input under mpirun exits 2 and writes nothing. With SUITE (suites/door-ajar-power-ci.json,
the CI size of the door-ajar cluster job), only that suite under `verify`, on 2 ranks against one
process. Prints one line per check and ends with "N passed, M failed".
"""

import json
import os
import signal
import subprocess
import sys
import tempfile

from jsonschema import validators

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402
from report_diff import differences  # noqa: E402

with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "results",
                       "report.schema.json"), encoding="utf-8") as schema_file:
    SCHEMA = json.load(schema_file)
VALIDATOR = validators.validator_for(SCHEMA)(SCHEMA)

SUITE = {
    "name": "mpi-check", "compare": "pairwise",
    "defaults": {"samples": 4000, "replicates": 7, "seed": 5},
    "runs": [
        {"estimator": "plain", "integrand": "genz-gaussian"},
        {"estimator": "pcbpt", "integrand": "genz-gaussian", "params": {"M": 8}},
        {"estimator": "plain", "integrand": "expr", "params": {"f": "sqrt(x0 - 0.001)"}},
        {"estimator": "plain", "integrand": "furnace", "params": {"resolution": 8},
         "samples": 8, "replicates": 5},
        {"estimator": "pt", "integrand": "furnace", "params": {"resolution": 8},
         "samples": 8, "replicates": 5},
        # Too few effective samples: escalated (4x, 16x) after the first stage.
        {"estimator": "plain", "integrand": "narrow-peak", "samples": 2000,
         "expect": "inconclusive"},
    ],
}


def mpirun(ranks):
    command = ["mpirun", "-np", str(ranks), "--oversubscribe"]
    return command + (["--allow-run-as-root"] if os.geteuid() == 0 else [])


def run(command, cwd):
    proc = subprocess.run(command, cwd=cwd, capture_output=True, encoding="utf-8", timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


def pixel_hashes(hasher, folder):
    names = sorted(n for n in os.listdir(folder) if n.endswith(".exr"))
    if not names:
        return {}
    out = subprocess.run([hasher] + names, cwd=folder, capture_output=True, encoding="utf-8",
                         check=True).stdout
    return dict(reversed(line.split()) for line in out.splitlines())


# The kill-and-resume suite: a rank is killed during its slow run; the finished ones are in rank
# 0's journal.
KILL_SUITE = {
    "name": "mpi-kill", "defaults": {"samples": 4000, "replicates": 6, "seed": 7},
    "runs": [
        {"estimator": "plain", "integrand": "genz-gaussian"},
        {"estimator": "pt", "integrand": "furnace", "params": {"resolution": 8}, "samples": 8},
        {"estimator": "plain", "integrand": "genz-oscillatory", "samples": 1500000},
        {"estimator": "lvc", "integrand": "genz-gaussian"},
    ],
}
BEFORE_SLOW = "[2/4] pt × furnace"


def rank_pids(launcher):
    """The ranks mpirun started, by rank (from their environment)."""
    out = {}
    for pid in os.listdir("/proc"):
        try:
            with open("/proc/%s/stat" % pid, encoding="utf-8") as f:
                parent = int(f.read().rsplit(")", 1)[1].split()[1])
            if parent != launcher:
                continue
            with open("/proc/%s/environ" % pid, "rb") as f:
                for item in f.read().split(b"\0"):
                    if item.startswith(b"OMPI_COMM_WORLD_RANK="):
                        out[int(item.split(b"=")[1])] = int(pid)
        except (OSError, ValueError, IndexError):
            continue
    return out


def kill_a_rank_during_slow_run(command, cwd):
    """Starts the job and kills rank 2 as the slow run starts; returns status and output."""
    proc = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            encoding="utf-8")
    seen = []
    for line in proc.stdout:
        seen.append(line)
        if line.startswith(BEFORE_SLOW):
            os.kill(rank_pids(proc.pid)[2], signal.SIGKILL)
            break
    rest, _ = proc.communicate(timeout=300)
    return proc.returncode, "".join(seen) + rest


def load(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def without_context(report):
    return {k: v for k, v in report.items() if k != "context"}


def same_as_one_process(binary, hasher, suite, ranks):
    """`verify SUITE` on `ranks` ranks against one process: exit status, report, images."""
    with tempfile.TemporaryDirectory(prefix="pcbench-mpi-") as tmp:
        command = [binary, "verify", suite, "--quiet"]
        one_status, out = run(command + ["-t", "2", "--out", "one"], tmp)
        check(one_status == 0, "%s in one process: exit 0" % os.path.basename(suite), out)
        status, out = run(mpirun(ranks) + command + ["-t", "1", "--out", "ranks"], tmp)
        check(status == one_status, "on %d ranks: exit %d as one process" % (ranks, status), out)
        diff = differences(without_context(load(os.path.join(tmp, "one", "report.json"))),
                           without_context(load(os.path.join(tmp, "ranks", "report.json"))))
        check(not diff, "on %d ranks: the report one process writes" % ranks, "; ".join(diff[:5]))
        images = pixel_hashes(hasher, os.path.join(tmp, "one", "images"))
        check(images and images == pixel_hashes(hasher, os.path.join(tmp, "ranks", "images")),
              "on %d ranks: the same %d images, pixel for pixel" % (ranks, len(images)))
    return summary()


def main():
    binary = os.path.abspath(sys.argv[1])
    hasher = os.path.abspath(sys.argv[2])
    if len(sys.argv) > 3:
        return same_as_one_process(binary, hasher, os.path.abspath(sys.argv[3]), 2)
    with tempfile.TemporaryDirectory(prefix="pcbench-mpi-") as tmp:
        with open(os.path.join(tmp, "suite.json"), "w", encoding="utf-8") as f:
            json.dump(SUITE, f)
        command = [binary, "verify", "suite.json", "--strategy-images", "--replicate-images"]
        one_status, out = run(command + ["-t", "2", "--out", "one"], tmp)
        check(one_status == 3, "one process: exit 3 (one run has non-finite samples)", out)
        one = load(os.path.join(tmp, "one", "report.json"))
        one_images = pixel_hashes(hasher, os.path.join(tmp, "one", "images"))
        stages = [len(r["escalation"]) for r in one["runs"] if r["integrand"] == "narrow-peak"]
        check(stages == [2], "one process: narrow-peak escalated twice", str(stages))
        check(len(one_images) > 10, "one process: scene images written", str(len(one_images)))

        for ranks in (2, 3):
            name = "np%d" % ranks
            status, out = run(mpirun(ranks) + command + ["-t", "1", "--out", name], tmp)
            check(status == one_status, "%s: exit %d as one process" % (name, status), out[-2000:])
            report = load(os.path.join(tmp, name, "report.json"))
            check(report["context"].get("mpi_ranks") == ranks and "mpi_ranks" not in one["context"],
                  "%s: context.mpi_ranks is %d (absent in one process)" % (name, ranks))
            errors = list(VALIDATOR.iter_errors(report))
            check(not errors, "%s: the report validates" % name,
                  errors[0].message if errors else "")
            diff = differences(without_context(one), without_context(report))
            check(not diff, "%s: the report one process writes, but timings" % name,
                  "; ".join(diff[:5]))
            images = pixel_hashes(hasher, os.path.join(tmp, name, "images"))
            check(images == one_images, "%s: the same %d images, pixel for pixel" %
                  (name, len(images)), str(set(images.items()) ^ set(one_images.items()))[:300])

        # Equal time: rank 0's pilot chooses the budget (as one process's pilot would, from its
        # own measurement); that budget as --samples in one process gives the same numbers.
        lvc = ["--estimator", "lvc", "--integrand", "genz-gaussian", "-r", "7", "--seed", "5",
               "--quiet"]
        status, out = run(mpirun(3) + [binary, "run"] + lvc + ["--seconds", "0.02", "-t", "1",
                                                              "--out", "timed"], tmp)
        timed = load(os.path.join(tmp, "timed", "report.json"))["runs"][0]
        status, out = run([binary, "run"] + lvc + ["--samples", str(timed["samples"]), "--out",
                                                  "given"], tmp)
        given = load(os.path.join(tmp, "given", "report.json"))["runs"][0]
        check(timed["budget"]["pilot_samples"] > 0 and [r["estimate"] for r in timed["replicates"]]
              == [r["estimate"] for r in given["replicates"]],
              "equal time on 3 ranks: the pilot's budget (%d samples) as --samples gives the same "
              "estimates" % timed["samples"])

        # pcbench reference over 2 ranks: the same converged image in the cache.
        reference = [binary, "reference", "--integrand", "furnace", "--param", "resolution=8",
                     "-n", "8", "-r", "5", "-t", "1"]
        status_one, out_one = run(reference + ["--reference-cache", "ref-one"], tmp)
        status_mpi, out_mpi = run(mpirun(2) + reference + ["--reference-cache", "ref-mpi"], tmp)
        check(status_one == 0 and status_mpi == 0, "reference: rendered in one process and on 2 "
              "ranks", out_one[-500:] + out_mpi[-500:])
        ref_one = pixel_hashes(hasher, os.path.join(tmp, "ref-one"))
        ref_mpi = pixel_hashes(hasher, os.path.join(tmp, "ref-mpi"))
        check(ref_one and ref_one == ref_mpi, "reference: the same image, pixel for pixel",
              str(ref_one) + " vs " + str(ref_mpi))

        # A rank killed mid-job stops the job, saying which; --resume finishes it on another
        # number of ranks with the report one process writes.
        with open(os.path.join(tmp, "kill.json"), "w", encoding="utf-8") as f:
            json.dump(KILL_SUITE, f)
        kill = [binary, "verify", "kill.json"]
        status, out = run(kill + ["-t", "2", "--out", "kill-one"], tmp)
        status, out = kill_a_rank_during_slow_run(mpirun(3) + kill + ["-t", "1", "--out", "killed"],
                                                  tmp)
        check(status != 0 and "rank 2" in out and "signal 9" in out,
              "a rank killed mid-job: the job stops naming it (exit %d)" % status, out[-1500:])
        saved = [n for n in os.listdir(os.path.join(tmp, "killed", "checkpoint"))
                 if n != "session.json" and n.endswith(".json")]
        check(len(saved) == 2, "a rank killed mid-job: the 2 runs before it are saved", str(saved))
        status, out = run(mpirun(2) + kill + ["-t", "1", "--out", "killed", "--resume"], tmp)
        check(status == 0 and out.count("restored from") == 2,
              "resumed on 2 ranks: the 2 saved runs restored", out[-1500:])
        diff = differences(without_context(load(os.path.join(tmp, "kill-one", "report.json"))),
                           without_context(load(os.path.join(tmp, "killed", "report.json"))))
        check(not diff, "resumed on 2 ranks: the report one process writes", "; ".join(diff[:5]))
        check(pixel_hashes(hasher, os.path.join(tmp, "kill-one", "images"))
              == pixel_hashes(hasher, os.path.join(tmp, "killed", "images")),
              "resumed on 2 ranks: the same images")

        # Bad input: rank 0 says so once, every rank stops, nothing is written.
        status, out = run(mpirun(2) + [binary, "verify", "suite.json", "--estimator", "plain",
                                       "--out", "bad"], tmp)
        check(status == 2 and out.count("give a suite file or --estimator") == 1
              and not os.path.exists(os.path.join(tmp, "bad")),
              "bad input on 2 ranks: exit 2, said once, nothing written", out[-800:])
    return summary()


if __name__ == "__main__":
    sys.exit(main())
