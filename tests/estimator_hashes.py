#!/usr/bin/python3
"""The bit-for-bit record of what the estimators compute (ctest `estimators.hashes`, label ci).

Usage:
    /usr/bin/python3 tests/estimator_hashes.py PATH/TO/pcbench PATH/TO/pcbench_exr_pixel_hash \
                     SOURCE_DIR [--write]

Runs the commands of commands() below (every scene estimator, pcbpt with each visibility and
guide, also in its two named designs, and the scene controls on the four built-in scenes at
32x32; the whole default suite at a small budget; ris, restir and the reuse controls, analytic
and on scenes) with 1 thread and with 2, and hashes per run
what the estimators determine:
  - the per-replicate estimates and their summaries (mean_abs, n, nonfinite, largest_abs,
    nonzero, effective_samples), the run's mean, standard error and mean_abs, the counters
    (scene_builds aside: it counts the process's BVH builds, not the run's work), and the
    strategy images' means and shares;
  - the pixel values of the mean, standard error and strategy EXR files (pcbench_exr_pixel_hash:
    the channels' bits, whatever the compression).
Verdicts, comparisons, p-values, detectable biases, errors against references, z maps and
timings are left out: they are the verifier's, not the estimators', and change with it.
Checks that 1 and 2 threads give the same hashes and that they match tests/data/
estimator_hashes.json; `--write` records them there instead (from the binary before a refactor:
the refactor must then pass unchanged). Exits 1 on any difference, naming the run.
"""

import hashlib
import json
import os
import subprocess
import sys
import tempfile

SCENE_ESTIMATORS = ["pt", "lt", "plain", "vc-all", "lvc", "pcbpt", "ctl-scene-visible-only",
                    "ctl-scene-lvc-per-vertex"]
SCENES = ["furnace", "cornell", "cornell-glossy", "door-ajar"]
# The grid of pcbpt's visibility and guide (read by pcbpt only) over its named designs.
PCBPT_GRID = {"visibility": "ignored,cache-point", "guide": "first,all"}


def pcbpt_design(binary, name):
    """`-p k=v` for each parameter of pcbpt's named configuration `name` (`pcbench list --json`,
    defined in estimators/scene/pcbpt_form.cpp) that the grid does not set."""
    listing = json.loads(subprocess.run([binary, "list", "--json"], check=True,
                                        capture_output=True, text=True).stdout)
    pcbpt = next(e for e in listing["estimators"] if e["name"] == "pcbpt")
    design = next(c for c in pcbpt["scene_configurations"] if c["name"] == name)
    return [a for k, v in design["params"].items() if k not in PCBPT_GRID
            for a in ("-p", f"{k}={v}")]


def commands(binary):
    """Arguments after `pcbench run`, by name."""
    pcbpt = ["-e", "pcbpt", "-i", ",".join(SCENES), "-p", "resolution=32"]
    for k, v in PCBPT_GRID.items():
        pcbpt += ["-p", f"{k}={v}"]
    scene_budget = ["-n", "4", "-r", "2", "-s", "1", "--strategy-images"]
    return {
        "scenes": ["-e", ",".join(SCENE_ESTIMATORS), "-i", ",".join(SCENES),
                   "-p", "resolution=32", "-p", "visibility=ignored,cache-point",
                   "-p", "guide=first,all"] + scene_budget,
        # pcbpt's legacy tile design: its runs keep the ids, random streams and numbers they had
        # before the published design.
        "pcbpt-legacy": pcbpt + pcbpt_design(binary, "legacy-tile") + scene_budget,
        # pcbpt's published design (its choices where pcbench's defaults differ): these runs keep
        # the ids and numbers they had as pcbpt's defaults.
        "pcbpt-published": pcbpt + pcbpt_design(binary, "published") + scene_budget,
        # Every row of the default suite (113 runs) at 2048 samples x 4 replicates instead of its
        # 10^5-10^6 x 32, which would take minutes.
        "analytic": ["suites/default.json", "-n", "2048", "-r", "4", "-s", "1"],
        # The reservoir estimators and their controls (issue 28), which the default suite leaves
        # out, at their defaults and with reuse over two rounds.
        "reservoir": ["-e", "ris,restir,ctl-naive-reuse,ctl-reuse-unshadowed",
                      "-i", "blocker,linear-emitter,genz-oscillatory", "-n", "2048", "-r", "4",
                      "-s", "1"],
        # Their scene forms and the scene reuse controls (ris, restir with each weighting and
        # visible targets).
        "scene-reservoir": ["-e", "ris,restir,ctl-scene-naive-reuse,ctl-scene-reuse-unshadowed",
                            "-i", "cornell,door-ajar,many-lights", "-p", "resolution=32"]
                           + scene_budget,
        "scene-reservoir-forms": ["-e", "restir", "-i", "cornell", "-p", "resolution=32",
                                  "-p", "weights=pairwise,count", "-p", "target=unshadowed,visible"]
                                 + scene_budget,
        "reservoir-rounds": ["-e", "restir", "-i", "blocker", "-p", "rounds=2",
                             "-p", "weights=balance,pairwise,count", "-p", "target=approx,f",
                             "-n", "2048", "-r", "4", "-s", "1"],
    }


THREADS = [1, 2]
RECORD = os.path.join("tests", "data", "estimator_hashes.json")

REPLICATE_TIMINGS = {"seconds", "cpu_seconds"}


def exr_hashes(tool, folder, files):
    paths = [os.path.join(folder, f) for f in files]
    out = subprocess.run([tool] + paths, check=True, capture_output=True, text=True).stdout
    return [line.split(" ", 1)[0] for line in out.splitlines()]


def determined(run, folder, tool):
    """What the estimator determines of one run, as one JSON-able value."""
    fields = {k: run.get(k) for k in ("id", "estimator", "integrand", "integrand_params",
                                      "params", "status", "samples", "replicates_requested",
                                      "pool")}
    fields["replicates"] = [{k: v for k, v in r.items() if k not in REPLICATE_TIMINGS}
                            for r in run.get("replicates", [])]
    aggregates = run.get("aggregates") or {}
    fields["aggregates"] = {k: aggregates.get(k) for k in ("mean", "stderr", "mean_abs")}
    fields["counters"] = {k: v for k, v in (run.get("counters") or {}).items()
                          if k != "scene_builds"}
    image = run.get("image")
    if image:
        fields["strategies"] = image.get("strategies")
        files = image.get("files") or {}
        names = [files[k] for k in ("mean", "stderr", "strategies") if files.get(k)]
        fields["exr"] = dict(zip(names, exr_hashes(tool, folder, names)))
    return fields


def hash_runs(binary, tool, source, name, args, threads, scratch):
    out = os.path.join(scratch, f"{name}-{threads}")
    cache = os.path.join(scratch, "no-reference-cache")  # no converged images: none are read
    os.makedirs(cache, exist_ok=True)
    command = [binary, "run"] + args + ["--threads", str(threads), "-q", "--out", out,
                                        "--reference-cache", cache]
    # Exit 1 (a verdict differs from its expectation) still writes the whole report: at this
    # budget some verdicts do, and verdicts are not what is recorded here.
    status = subprocess.run(command, cwd=source, stdout=subprocess.DEVNULL).returncode
    if status not in (0, 1):
        raise SystemExit(f"{' '.join(command)}: exit {status}")
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    runs = {}
    for run in report["runs"]:
        value = determined(run, out, tool)
        digest = hashlib.sha256(json.dumps(value, sort_keys=True).encode()).hexdigest()
        label = f"{run['estimator']} {run['integrand']} {json.dumps(run.get('params'))}"
        # The numbers alone, without the parameters the report lists: a run whose parameter
        # list grew (a new parameter at its legacy value) keeps them.
        numbers = {k: v for k, v in value.items() if k != "params"}
        runs[run["id"]] = {"run": label, "hash": digest, "numbers": hashlib.sha256(
            json.dumps(numbers, sort_keys=True).encode()).hexdigest()}
    return runs


def main():
    binary, tool, source = (os.path.abspath(a) for a in sys.argv[1:4])
    write = "--write" in sys.argv[4:]
    failures = []
    runs_of = commands(binary)
    record = {"commands": {n: "pcbench run " + " ".join(a) + " --threads T -q --out DIR "
                              "--reference-cache EMPTY_DIR" for n, a in runs_of.items()},
              "made_by": "tests/estimator_hashes.py PCBENCH PCBENCH_EXR_PIXEL_HASH SOURCE_DIR "
                         "--write",
              "threads": THREADS, "runs": {}}
    with tempfile.TemporaryDirectory(prefix="pcbench-hashes-") as scratch:
        for name, args in runs_of.items():
            by_threads = [hash_runs(binary, tool, source, name, args, t, scratch)
                          for t in THREADS]
            for t, runs in zip(THREADS[1:], by_threads[1:]):
                for run_id, entry in by_threads[0].items():
                    if runs.get(run_id) != entry:
                        failures.append(f"{name}: {entry['run']} ({run_id}) differs with {t} "
                                        "threads")
            record["runs"][name] = by_threads[0]
    path = os.path.join(source, RECORD)
    if write:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            json.dump(record, f, indent=1, sort_keys=True)
            f.write("\n")
        print(f"wrote {path}")
    else:
        with open(path) as f:
            expected = json.load(f)
        for name, runs in expected["runs"].items():
            got = record["runs"].get(name, {})
            for run_id, entry in runs.items():
                if run_id not in got:
                    failures.append(f"{name}: {entry['run']} ({run_id}) was not run")
                elif got[run_id]["numbers"] != entry["numbers"]:
                    failures.append(f"{name}: {entry['run']} ({run_id}) changed")
                elif got[run_id]["hash"] != entry["hash"]:
                    # Same id and numbers, a longer parameter list (a new parameter at its
                    # legacy value): not a change of behaviour; --write records the new list.
                    print(f"note    {name}: {got[run_id]['run']} ({run_id}): same numbers, "
                          "parameters listed differ")
            for run_id, entry in got.items():
                if run_id not in runs:
                    failures.append(f"{name}: {entry['run']} ({run_id}) is not recorded")
    total = sum(len(r) for r in record["runs"].values())
    for f in failures:
        print("FAILED  " + f)
    print(f"{total} runs hashed with {THREADS} threads, {len(failures)} differences")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
