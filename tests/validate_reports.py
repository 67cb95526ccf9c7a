#!/usr/bin/python3
"""Runs pcbench on configurations that produce every report shape and checks each report.json.

Usage (ctest test `report.schema`):
    /usr/bin/python3 tests/validate_reports.py PATH/TO/pcbench SOURCE_DIR

Each report is validated against SOURCE_DIR/results/report.schema.json (python3-jsonschema, the
validator class named by the schema's $schema, format checking off), then checked for what the
schema cannot express: non-finite numbers written as null and named in `nonfinite_fields`, the
exit status agreeing with the statuses and verdicts, determinism across placement, and so on.
Negative tests make sure the schema and the semantic checks can fail. Prints one line per check
and ends with "N passed, M failed"; exits 1 if any check failed.
"""

import copy
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

try:
    import jsonschema
    from jsonschema import validators
except ImportError:  # the `python3` on PATH may not be Debian's
    print("jsonschema is not importable by %s; run this with /usr/bin/python3 "
          "(Debian's python3-jsonschema)" % sys.executable)
    print("0 passed, 1 failed")
    sys.exit(1)

RUN_TIMEOUT = 600  # seconds per pcbench invocation


class Checks:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, condition, what, detail=""):
        if condition:
            self.passed += 1
            print("PASS  " + what, flush=True)
        else:
            self.failed += 1
            print("FAIL  " + what + (": " + detail if detail else ""), flush=True)
        return bool(condition)


checks = Checks()
check = checks.check


# --- running pcbench ------------------------------------------------------------------------

def run_pcbench(binary, args, cwd):
    """Runs pcbench; returns (exit status, stdout, stderr)."""
    try:
        proc = subprocess.run([binary] + args, cwd=cwd, capture_output=True,
                              encoding="utf-8", errors="replace", timeout=RUN_TIMEOUT)
    except subprocess.TimeoutExpired:
        return None, "", "timed out after %d s" % RUN_TIMEOUT
    return proc.returncode, proc.stdout, proc.stderr


def wait_for_sigint_handler(pid, timeout):
    """Waits until process `pid` catches SIGINT (Linux: bit 2 of SigCgt in /proc/PID/status).
    pcbench installs its handler first thing in main(), but loading its libraries can take
    seconds on a loaded machine, and a SIGINT before that kills it (status -2), which is not
    what the test is about. Elsewhere it waits 1 s."""
    status_file = f"/proc/{pid}/status"
    if not os.path.exists(status_file):
        time.sleep(1.0)
        return
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            with open(status_file) as f:
                caught = next((int(line.split()[1], 16) for line in f
                               if line.startswith("SigCgt:")), 0)
        except OSError:
            return  # it has ended
        if caught & (1 << (signal.SIGINT - 1)):
            return
        time.sleep(0.05)


def run_and_interrupt(binary, args, cwd):
    """Starts pcbench, sends SIGINT 1 s after its handler is installed (during its first run,
    which takes ~10 s; or before it starts on a loaded machine: either way no run finishes);
    returns (status, out, err)."""
    proc = subprocess.Popen([binary] + args, cwd=cwd, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, encoding="utf-8", errors="replace")
    first = ""
    wait_for_sigint_handler(proc.pid, timeout=60)
    time.sleep(1.0)
    if proc.poll() is not None:
        out, err = proc.communicate()
        return proc.returncode, out, first + err + "\n(finished before it could be interrupted)"
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        return None, out, first + err + "\n(did not stop within 120 s of SIGINT)"
    return proc.returncode, out, first + err


def load_report(folder):
    path = os.path.join(folder, "report.json")
    try:
        with open(path, encoding="utf-8") as f:
            # JSON has no NaN/Infinity: refuse them rather than let Python accept them.
            def no_constants(name):
                raise ValueError("non-JSON constant %s" % name)
            return json.load(f, parse_constant=no_constants), None
    except (OSError, ValueError) as e:
        return None, str(e)


# --- checks that the schema cannot express -----------------------------------------------------

def resolve(obj, path):
    """Follows a /-separated path relative to `obj`; returns (found, value)."""
    for part in path.split("/"):
        if isinstance(obj, dict) and part in obj:
            obj = obj[part]
        elif isinstance(obj, list) and part.isdigit() and int(part) < len(obj):
            obj = obj[int(part)]
        else:
            return False, None
    return True, obj


def semantic_problems(report, exit_status=None):
    """Problems with a schema-valid report that the schema cannot see; [] when none."""
    problems = []
    runs = report["runs"]
    ids = [r["id"] for r in runs]
    if len(set(ids)) != len(ids):
        problems.append("run ids are not unique: %s" % ids)
    seed = report["context"]["seed"]
    for index, run in enumerate(runs):
        where = "runs/%d (%s x %s)" % (index, run["estimator"], run["integrand"])
        listed = run["nonfinite_fields"]
        # Every listed path names a null.
        for path in listed:
            found, value = resolve(run, path)
            if not found:
                problems.append("%s: nonfinite_fields entry %r does not resolve" % (where, path))
            elif value is not None:
                problems.append("%s: nonfinite_fields entry %r is %r, not null"
                                % (where, path, value))
        # Every null that can only mean "non-finite" is listed.
        must_be_listed = []
        for r, rep in enumerate(run["replicates"]):
            for key in ("estimate", "variance", "mean_abs"):
                if key == "variance" and run["pool"] == "shared":
                    continue  # samples sharing a pool have no within-replicate variance
                if rep[key] is None:
                    must_be_listed.append("replicates/%d/%s" % (r, key))
        aggregates = run["aggregates"]
        if aggregates is not None:
            reference = run["reference"]
            has_reference = reference["kind"] != "none"
            for key, value in aggregates.items():
                if value is not None:
                    continue
                if key in ("bias", "rmse") and not has_reference:
                    continue  # undefined by design
                if key == "rel_mse" and (not has_reference or reference["value"] == 0):
                    continue  # undefined by design
                if key == "rmse_slope" and (not has_reference or len(run["series"]) < 3):
                    continue  # undefined by design: no RMSE, or too few points to fit
                must_be_listed.append("aggregates/" + key)
        verdict = run["verdict"]
        if verdict is not None and verdict["test"] != "none":
            # A test that ran has every figure defined; a null there was a NaN or an infinity
            # (min_detectable_rel_bias excepted: undefined by design when the reference is 0).
            for key in ("statistic", "dof", "p_value", "p_adjusted", "min_detectable_bias",
                        "min_detectable_rel_bias"):
                if verdict.get(key, 0) is not None:
                    continue
                if key == "min_detectable_rel_bias" and run["reference"]["value"] == 0:
                    continue
                must_be_listed.append("verdict/" + key)
        for path in must_be_listed:
            if path not in listed:
                problems.append("%s: %s is null but not named in nonfinite_fields" % (where, path))
        # Replicates agree with the run.
        nonfinite = 0
        for r, rep in enumerate(run["replicates"]):
            nonfinite += rep["nonfinite"]
            if rep["n"] != run["samples"]:
                problems.append("%s: replicates/%d/n = %d, samples = %d"
                                % (where, r, rep["n"], run["samples"]))
            if rep["nonfinite"] > rep["n"]:
                problems.append("%s: replicates/%d has more non-finite samples than samples"
                                % (where, r))
            largest = rep["largest_abs"]
            if largest != sorted(largest, reverse=True):
                problems.append("%s: replicates/%d/largest_abs is not largest first" % (where, r))
            if len(largest) > rep["n"] - rep["nonfinite"]:
                problems.append("%s: replicates/%d/largest_abs has more values than finite samples"
                                % (where, r))
            if rep["nonfinite"] > 0 and rep["estimate"] is not None:
                problems.append("%s: replicates/%d has non-finite samples but a finite estimate"
                                % (where, r))
        status = run["status"]
        if status in ("ok", "invalid"):
            if not run["replicates"]:
                problems.append("%s: a finished run without replicates" % where)
            if (status == "invalid") != (nonfinite > 0):
                problems.append("%s: status %s with %d non-finite samples"
                                % (where, status, nonfinite))
        first = run["first_nonfinite"]
        if (first is not None) != (nonfinite > 0):
            problems.append("%s: first_nonfinite is %r with %d non-finite samples"
                            % (where, first, nonfinite))
        if first is not None:
            if first["seed"] != seed:
                problems.append("%s: first_nonfinite.seed %d != context seed %d"
                                % (where, first["seed"], seed))
            r = first["replicate"]
            if r >= len(run["replicates"]) or run["replicates"][r]["nonfinite"] == 0:
                problems.append("%s: first_nonfinite names replicate %d, which has no non-finite "
                                "sample" % (where, r))
            elif any(rep["nonfinite"] > 0 for rep in run["replicates"][:r]):
                problems.append("%s: first_nonfinite is not the first replicate with one" % where)
            elif first["sample"] >= run["samples"]:
                problems.append("%s: first_nonfinite.sample out of range" % where)
        if verdict is not None and aggregates is None:
            problems.append("%s: a verdict without aggregates" % where)
    # A suite's comparisons pair its own runs; `pcbench compare` pairs runs of two other reports
    # and writes no runs of its own.
    for c in report["comparisons"] if report["runs"] else []:
        for key in ("a", "b"):
            # A scene's exact image, and the tile test's self-check on a run, are named so.
            side = c[key][:-len("+injected")] if c[key].endswith("+injected") else c[key]
            if side not in ids and side != "exact":
                problems.append("comparison %s-%s: %s is not a run id" % (c["a"], c["b"], key))
    if exit_status is not None:
        expected = expected_exit_status(report)
        if exit_status != expected:
            problems.append("exit status %s, but the report implies %d" % (exit_status, expected))
    return problems


def expected_exit_status(report):
    """The exit status docs/reference/INTERFACE.md prescribes for a report's runs and
    comparisons."""
    runs = report["runs"]
    if any(r["status"] == "not_run" for r in runs):
        return 130
    outcomes = [r["verdict"] for r in runs if r["verdict"] is not None] + report["comparisons"]
    outcomes += report.get("exact_checks", []) + [e["verdict"] for e in report.get("external", [])]
    if any(o["result"] != o["expect"] for o in outcomes):
        return 1
    if any(r["status"] in ("error", "invalid") for r in runs):
        return 3
    return 0


# --- main -------------------------------------------------------------------------------------

def schema_errors(validator, instance):
    return sorted(validator.iter_errors(instance), key=lambda e: list(e.absolute_path))


def describe(errors, limit=3):
    text = "; ".join("%s: %s" % ("/".join(str(p) for p in e.absolute_path) or "/", e.message)
                     for e in errors[:limit])
    return text + (" (and %d more)" % (len(errors) - limit) if len(errors) > limit else "")


def main():
    if len(sys.argv) != 3:
        print("usage: validate_reports.py PATH/TO/pcbench SOURCE_DIR")
        print("0 passed, 1 failed")
        return 2
    binary = os.path.abspath(sys.argv[1])
    source_dir = os.path.abspath(sys.argv[2])
    schema_path = os.path.join(source_dir, "results", "report.schema.json")

    with open(schema_path, encoding="utf-8") as f:
        schema = json.load(f)
    validator_class = validators.validator_for(schema, default=None)
    if not check(validator_class is not None, "schema names a known $schema dialect",
                 repr(schema.get("$schema"))):
        print("%d passed, %d failed" % (checks.passed, checks.failed))
        return 1
    try:
        validator_class.check_schema(schema)
        schema_ok = True
        detail = ""
    except jsonschema.exceptions.SchemaError as e:
        schema_ok = False
        detail = e.message
    check(schema_ok, "schema is valid against its metaschema (%s)" % validator_class.__name__,
          detail)
    validator = validator_class(schema)  # no format_checker: format is an annotation only

    # name, args, expected exit status, extra checks(report) -> list of (ok, what, detail)
    suite = {
        "name": "schema-check",
        "description": "every report shape the schema test needs",
        "defaults": {"samples": 1000, "replicates": 3, "seed": 7},
        "runs": [
            {"estimator": "plain", "integrand": "expr",
             "params": {"f": "x0*y0", "exact": 0.25}, "expect": "consistent"},
            # Zero variance: efficiency is infinite, so null and named, in an ok run.
            {"estimator": "plain", "integrand": "expr",
             "params": {"f": "1", "exact": 1}, "samples": 500},
        ],
        "grid": [
            {"estimator": ["plain"], "integrand": ["genz-gaussian", "genz-oscillatory"],
             "params": {"sharpness": [2, 4]}},
        ],
    }

    reports = {}
    with tempfile.TemporaryDirectory(prefix="pcbench-schema-") as tmp:
        estimates_path = os.path.join(tmp, "estimates.csv")
        with open(estimates_path, "w", encoding="utf-8") as f:
            f.write("estimate\n" + "\n".join("%.6f" % (0.5 + 0.01 * ((i * 37) % 11 - 5) / 5)
                                               for i in range(20)) + "\n")
        suite_path = os.path.join(tmp, "suite.json")
        with open(suite_path, "w", encoding="utf-8") as f:
            json.dump(suite, f, indent=2)

        # A converged image in a reference cache, for a scene report measured against it.
        references = os.path.join(tmp, "references")
        status, _, err = run_pcbench(binary, ["reference", "-i", "cornell", "-p", "resolution=8",
                                              "-n", "8", "-r", "4", "--reference-cache",
                                              references], tmp)
        check(status == 0, "pcbench reference fills a reference cache", err.strip()[-500:])

        cases = [
            ("a-one-run", ["run", "-e", "plain", "-i", "genz-gaussian", "-n", "2000", "-r", "4"],
             0, False),
            # Interleaved replicates: the report has efficiency ratios.
            ("a-interleaved", ["run", "-e", "plain,pcbpt", "-i", "genz-gaussian", "-n", "2000",
                               "-r", "4", "--interleave"], 0, False),
            ("b-nonfinite", ["run", "-e", "plain", "-i", "expr", "-p", "f=1/(x0-x0)", "-n", "1000",
                             "-r", "4"], 3, False),
            ("c-no-reference", ["run", "-e", "plain", "-i", "expr", "-p", "f=x0*y0", "-n", "1000",
                                "-r", "4", "--seed", "5"],
             0, False),
            ("d-cli-grid", ["run", "-e", "plain", "-i", "genz-gaussian,genz-oscillatory",
                            "-n", "2000", "-r", "4"], 0, False),
            ("e-suite", ["run", suite_path], 0, False),
            # Every replicate gives the same wrong value: no spread, so it is tested against the
            # rounding bound (a finite t); the verdict is biased against expectation: exit 1.
            ("g-constant-biased", ["run", "-e", "plain", "-i", "expr", "-p", "f=1", "-p",
                                   "exact=2", "-n", "100", "-r", "3"], 1, False),
            # The verifier's report shapes: exact checks, a negative control on its declared
            # workload (flagged: exit 0), replicate estimates from a file, and a comparison.
            ("h-verify-exact", ["verify", "--exact", "-e", "ctl-wrong-count,pcbpt", "-i",
                                "form-factor"], 0, False),
            ("i-verify-control", ["verify", "-e", "ctl-wrong-count", "-n", "20000", "-r", "8"],
             0, False),
            ("j-verify-estimates", ["verify", "--estimates", estimates_path, "--reference",
                                    "0.5+-0.001"], 0, False),
            ("k-compare", ["compare", os.path.join(tmp, "a-one-run", "report.json"),
                           os.path.join(tmp, "d-cli-grid", "report.json")], 0, False),
            ("l-calibrate", ["calibrate", "-e", "plain", "--seeds", "50", "-n", "200", "-r", "4"],
             0, False),
            # The block pyramid's calibration on scenes: a `tile_calibration` section, no runs.
            ("l-tile-calibrate", ["calibrate", "-i", "furnace,cornell", "-p", "resolution=16",
                                  "--seeds", "20", "-n", "1", "-r", "4"], 0, False),
            ("l-tile-calibrate-paired", ["calibrate", "-i", "cornell", "-p", "resolution=16",
                                         "--seeds", "20", "-n", "1", "-r", "4", "--paired"],
             0, False),
            # Scenes: image sections (with the per-strategy images), tracing counters, tile
            # comparisons (against the exact furnace, between estimators, the injected
            # self-check) and a flagged control.
            ("m-scene", ["verify", "-e", "plain,pcbpt,ctl-scene-lvc-per-vertex", "-i",
                         "furnace,cornell", "-p", "resolution=8", "-n", "4", "-r", "4",
                         "--strategy-images"], 0, False),
            # Paired streams: runs with "streams": "paired" and paired block pyramids.
            ("m-scene-paired", ["run", "-e", "pt,plain", "-i", "cornell", "-p", "resolution=8",
                                "-n", "2", "-r", "4", "--paired"], 0, False),
            # Errors against the cached converged image: reference "cache" with its provenance.
            ("n-scene-cached", ["run", "-e", "plain,pcbpt", "-i", "cornell", "-p", "resolution=8",
                                "-n", "2", "-r", "4", "--reference-cache", references], 0, False),
            # Interrupted during the first of two long runs: both not_run, exit 130.
            ("f-interrupted", ["run", "-e", "plain", "-i", "genz-gaussian,genz-oscillatory",
                               "-n", "100000000", "-r", "8"], 130, True),
        ]
        for name, args, expected_status, interrupt in cases:
            out_dir = os.path.join(tmp, name)
            full_args = args + ["--out", out_dir]
            if interrupt:
                status, out, err = run_and_interrupt(binary, full_args, tmp)
            else:
                status, out, err = run_pcbench(binary, full_args, tmp)
            check(status == expected_status,
                  "%s: pcbench %s exits %d" % (name, " ".join(args), expected_status),
                  "exit status %s; stderr: %s" % (status, err.strip()[-500:]))
            report, problem = load_report(out_dir)
            if not check(report is not None, "%s: report.json is written and parses" % name,
                         problem or ""):
                continue
            errors = schema_errors(validator, report)
            check(not errors, "%s: report validates against the schema" % name, describe(errors))
            if errors:
                continue
            problems = semantic_problems(report, status)
            check(not problems,
                  "%s: semantic checks (nonfinite_fields, statuses, exit status)" % name,
                  "; ".join(problems[:5]))
            reports[name] = report

    # --- per-case expectations -----------------------------------------------------------------
    tiles = reports.get("l-tile-calibrate")
    if tiles:
        section = tiles["tile_calibration"]
        check(tiles["suite"] == "tile calibration" and tiles["runs"] == []
              and "calibration" not in tiles,
              "l-tile-calibrate: a tile_calibration section and no runs")
        check([(r["scene"], r["estimator_a"], r["estimator_b"]) for r in section["rows"]]
              == [("furnace", "pt", "exact"), ("furnace", "plain", "exact"),
                  ("cornell", "pt", "plain")]
              and all(len(r["min_p_adjusted"]) == 20 for r in section["rows"]),
              "l-tile-calibrate: furnace against its exact image, cornell pt vs plain, 20 seeds")
        check(all([(s["block"], s["tests"], len(s["min_p_adjusted"])) for s in r["scales"]]
                  == [(8, 12, 20), (16, 3, 20)] and r["tests"] == 15 for r in section["rows"]),
              "l-tile-calibrate: every row has its pyramid's scales, 8 px (12 tests) and the "
              "whole image (3), with a smallest adjusted p per seed")
        curves = section["power_curves"]
        check([(c["block_rule"], c["block"]) for c in curves]
              == [("brightest", 8), ("brightest", 16), ("centre", 8), ("centre", 16)]
              and all([p["multiplier"] for p in c["points"]] == [0.5, 1, 2] for c in curves),
              "l-tile-calibrate: power curves in the brightest and the centre block of each scale "
              "at k = 0.5, 1, 2")
    cached = reports.get("n-scene-cached")
    if cached:
        images = [run["image"] for run in cached["runs"]]
        check(all(i["reference"] == "cache" and i["reference_cache"]["samples_per_pixel"] == 8
                  and i["reference_rel_variance"] > 0 for i in images),
              "n-scene-cached: errors against the cached image, with its provenance and variance")
    m = reports.get("m-scene")
    if m:
        imaged = [r for r in m["runs"] if r.get("image")]
        check(imaged and all(r["image"]["files"].get("strategies") and r["image"]["strategies"]
                             for r in imaged),
              "m-scene: every run with images names its strategy file and lists its strategies")
        check(all(abs(sum(x["share"] for x in r["image"]["strategies"]) - 1.0) < 1e-9
                  for r in imaged),
              "m-scene: each run's strategy shares sum to 1")

    a = reports.get("a-one-run")
    if a:
        run = a["runs"][0]
        check(len(a["runs"]) == 1 and run["status"] == "ok" and run["error"] is None,
              "a-one-run: one run, status ok, error null")
        check(run["reference"]["kind"] == "exact" and run["verdict"]["test"] == "student_t"
              and run["verdict"]["result"] == run["verdict"]["expect"] == "consistent",
              "a-one-run: exact reference, student_t verdict, consistent as expected",
              json.dumps(run["verdict"]))
        check(run["nonfinite_fields"] == []
              and all(v is not None for k, v in run["aggregates"].items()
                      if k != "rmse_slope")  # two series points: no slope by design
              and len(run["replicates"]) == 4,
              "a-one-run: 4 replicates, every aggregate finite, nothing non-finite")
        check(a["context"]["seed"] == 1 and a["context"]["argv"][1:3] == ["run", "-e"],
              "a-one-run: context records seed 1 (default) and argv")

    b = reports.get("b-nonfinite")
    if b:
        run = b["runs"][0]
        listed = run["nonfinite_fields"]
        check(run["status"] == "invalid" and run["verdict"] is None
              and run["aggregates"] is not None,
              "b-nonfinite: status invalid, verdict null, aggregates present",
              "status %s" % run["status"])
        expected = ["replicates/%d/%s" % (r, k) for r in range(4) for k in ("estimate", "variance")]
        check(all(run["replicates"][r][k] is None
                  for r in range(4) for k in ("estimate", "variance"))
              and all(p in listed for p in expected),
              "b-nonfinite: every replicate estimate/variance is null and named",
              json.dumps(listed))
        replay = run["first_nonfinite"].get("replay", "")
        check(replay.startswith("pcbench replay -e plain -i expr ")
              and replay.endswith("--replicate 0 --sample 0 --run-id " + run["id"]),
              "b-nonfinite: first_nonfinite.replay replays sample 0 of replicate 0 of the run",
              replay)
        check(run["aggregates"]["mean"] is None and "aggregates/mean" in listed
              and run["aggregates"]["stderr"] is None and "aggregates/stderr" in listed,
              "b-nonfinite: aggregates mean/stderr null and named")
        check(run["reference"]["kind"] == "none" and not any(p in listed for p in
              ("aggregates/bias", "aggregates/rmse", "aggregates/rel_mse")),
              "b-nonfinite: bias/rmse/rel_mse (undefined without a reference) are not named")
        check({k: run["first_nonfinite"][k] for k in ("seed", "replicate", "sample")}
              == {"seed": 1, "replicate": 0, "sample": 0},
              "b-nonfinite: first_nonfinite is seed 1, replicate 0, sample 0",
              json.dumps(run["first_nonfinite"]))
        check(all(rep["nonfinite"] == rep["n"] == 1000 and rep["largest_abs"] == []
                  for rep in run["replicates"]),
              "b-nonfinite: every sample counted as non-finite, none in largest_abs")
        check(isinstance(run["error"], str) and "non-finite" in run["error"],
              "b-nonfinite: error explains the non-finite samples", repr(run["error"]))

    c = reports.get("c-no-reference")
    if c:
        run = c["runs"][0]
        ref, verdict, agg = run["reference"], run["verdict"], run["aggregates"]
        check(run["status"] == "ok" and ref["kind"] == "none" and ref["value"] is None
              and ref["uncertainty"] is None and ref["dof"] is None,
              "c-no-reference: status ok, reference kind none with null value/uncertainty/dof",
              json.dumps(ref))
        check(verdict is not None and verdict["test"] == "none"
              and verdict["result"] == "inconclusive" and verdict["expect"] == "inconclusive",
              "c-no-reference: verdict test none, inconclusive as expected", json.dumps(verdict))
        check(agg["bias"] is None and agg["rmse"] is None and agg["rel_mse"] is None
              and agg["mean"] is not None and run["nonfinite_fields"] == [],
              "c-no-reference: bias/rmse/rel_mse null but not named non-finite")
        check(c["context"]["seed"] == 5, "c-no-reference: context records --seed 5")

    g = reports.get("g-constant-biased")
    if g:
        verdict = g["runs"][0]["verdict"]
        check(verdict["result"] == "biased" and verdict["statistic"] is not None
              and verdict["rounding_bound"] > 0
              and "tested against the rounding bound" in verdict["reason"]
              and g["runs"][0]["aggregates"]["stderr"] == 0,
              "g-constant-biased: no spread, tested against the rounding bound, biased",
              json.dumps(verdict))

    d = reports.get("d-cli-grid")
    if d:
        check([r["integrand"] for r in d["runs"]] == ["genz-gaussian", "genz-oscillatory"]
              and all(r["status"] == "ok" for r in d["runs"]),
              "d-cli-grid: two ok runs, genz-gaussian then genz-oscillatory",
              str([(r["integrand"], r["status"]) for r in d["runs"]]))
        if a:
            same = [r for r in d["runs"] if r["id"] == a["runs"][0]["id"]]
            check(len(same) == 1, "d-cli-grid: the genz-gaussian run has the id of a-one-run's run")
            if same:
                check([rep["estimate"] for rep in same[0]["replicates"]]
                      == [rep["estimate"] for rep in a["runs"][0]["replicates"]],
                      "d-cli-grid: same id and seed give the same estimates as a-one-run "
                      "(independent of the place in a grid)")

    e = reports.get("e-suite")
    if e:
        check(e["suite"] == "schema-check", "e-suite: report names the suite", repr(e["suite"]))
        check(len(e["runs"]) == 6 and all(r["status"] == "ok" for r in e["runs"]),
              "e-suite: 2 runs + a 2x2 grid give 6 ok runs",
              str([(r["integrand"], r["status"]) for r in e["runs"]]))
        check(e["context"]["seed"] == 7, "e-suite: context records the suite's default seed 7")
        check(all(r["samples"] == 1000 and len(r["replicates"]) == 3 for r in e["runs"]
                  if r["params"].get("f") != "1"),
              "e-suite: defaults (1000 samples x 3 replicates) applied")
        constant = [r for r in e["runs"] if r["params"].get("f") == "1"]
        if check(len(constant) == 1 and constant[0]["samples"] == 500,
                 "e-suite: the constant row keeps its own 500 samples"):
            run = constant[0]
            check(run["aggregates"]["efficiency"] is None
                  and "aggregates/efficiency" in run["nonfinite_fields"]
                  and run["aggregates"]["stderr"] == 0,
                  "e-suite: zero variance gives efficiency null and named, in an ok run",
                  json.dumps(run["aggregates"]) + " " + json.dumps(run["nonfinite_fields"]))
        sharp = sorted((r["integrand"], r["params"].get("sharpness")) for r in e["runs"]
                       if r["integrand"].startswith("genz"))
        check(sharp == [("genz-gaussian", 2), ("genz-gaussian", 4),
                        ("genz-oscillatory", 2), ("genz-oscillatory", 4)],
              "e-suite: grid expands to both integrands x sharpness 2, 4", str(sharp))

    f = reports.get("f-interrupted")
    if f:
        check(len(f["runs"]) == 2 and all(r["status"] == "not_run" for r in f["runs"]),
              "f-interrupted: both runs not_run", str([r["status"] for r in f["runs"]]))
        check(all(r["aggregates"] is None and r["verdict"] is None and r["replicates"] == []
                  and isinstance(r["error"], str) for r in f["runs"]),
              "f-interrupted: no replicates, aggregates or verdict; error says why")

    # --- negative tests: the schema and the semantic checks can fail ------------------------------
    def rejected(base, label, mutate):
        if base is None:
            check(False, "negative: %s (no report to mutate)" % label)
            return
        bad = copy.deepcopy(base)
        mutate(bad)
        errors = schema_errors(validator, bad)
        check(bool(errors), "negative: schema rejects %s" % label,
              "accepted a report it should reject")

    def delete(path):
        def mutate(report):
            *parents, last = path
            obj = report
            for p in parents:
                obj = obj[p]
            del obj[last]
        return mutate

    def assign(path, value):
        def mutate(report):
            *parents, last = path
            obj = report
            for p in parents:
                obj = obj[p]
            obj[last] = value
        return mutate

    rejected(a, 'runs[0].status "bogus"', assign(["runs", 0, "status"], "bogus"))
    rejected(a, "a report without runs[0].id", delete(["runs", 0, "id"]))
    rejected(a, "runs[0].id not 16 hex digits", assign(["runs", 0, "id"], "A09CB04628ECC24"))
    rejected(a, "schema_version 2", assign(["schema_version"], 2))
    rejected(a, "a report without context", delete(["context"]))
    rejected(a, 'git_dirty "unknown" (must be boolean or null)',
             assign(["context", "git_dirty"], "unknown"))
    rejected(a, "reference.kind \"guess\"", assign(["runs", 0, "reference", "kind"], "guess"))
    rejected(a, "verdict.result \"maybe\"", assign(["runs", 0, "verdict", "result"], "maybe"))
    rejected(a, "replicates[0].n = -1", assign(["runs", 0, "replicates", 0, "n"], -1))
    rejected(a, "replicates[0].n = 2000.5", assign(["runs", 0, "replicates", 0, "n"], 2000.5))
    rejected(a, "replicates[0].estimate as a string",
             assign(["runs", 0, "replicates", 0, "estimate"], "0.19"))
    rejected(a, "17 values in largest_abs",
             assign(["runs", 0, "replicates", 0, "largest_abs"], [1.0] * 17))
    rejected(a, "negative seconds", assign(["runs", 0, "replicates", 0, "seconds"], -1.0))
    rejected(a, "an ok run with a null verdict", assign(["runs", 0, "verdict"], None))
    rejected(a, "nonfinite_fields holding a number", assign(["runs", 0, "nonfinite_fields"], [3]))
    rejected(a, "a counter that is not an integer",
             assign(["runs", 0, "counters", "camera_paths"], 1.5))
    rejected(a, "first_nonfinite without sample",
             assign(["runs", 0, "first_nonfinite"], {"seed": 1, "replicate": 0}))
    rejected(a, "a comparison without expect",
             assign(["comparisons"], [{"a": "0123456789abcdef", "b": "fedcba9876543210",
                                       "test": "welch", "statistic": 0.1, "p_value": 0.9,
                                       "p_adjusted": 1.0, "alpha": 0.01,
                                       "result": "consistent"}]))
    rejected(a, "a comparison with a negative stderr_a",
             assign(["comparisons"], [{"a": "0123456789abcdef", "b": "0123456789abcdef",
                                       "test": "welch", "statistic": 0.1, "p_value": 0.9,
                                       "p_adjusted": 1.0, "alpha": 0.01, "result": "consistent",
                                       "expect": "consistent", "stderr_a": -1.0}]))
    rejected(c, "reference kind none with a value",
             assign(["runs", 0, "reference", "value"], 0.25))
    rejected(c, 'verdict test "none" with result consistent',
             assign(["runs", 0, "verdict", "result"], "consistent"))
    rejected(b, "an invalid run without first_nonfinite",
             assign(["runs", 0, "first_nonfinite"], None))
    rejected(b, "first_nonfinite.replay that is not a pcbench replay command",
             assign(["runs", 0, "first_nonfinite", "replay"], "rm -rf /"))
    m_imaged = next((i for i, r in enumerate((m or {}).get("runs", [])) if r.get("image")), None)
    if m_imaged is not None:
        rejected(m, "a strategy without its light vertex count s",
                 delete(["runs", m_imaged, "image", "strategies", 0, "s"]))
        rejected(m, "a strategy layer name that is not s<s>_t<t>",
                 assign(["runs", m_imaged, "image", "strategies", 0, "layer"], "bdpt"))

    # A well-formed comparison and image are accepted (they are not produced yet).
    if a:
        good = copy.deepcopy(a)
        good["comparisons"] = [{"a": good["runs"][0]["id"], "b": "fedcba9876543210",
                                "test": "welch", "statistic": 0.1, "p_value": 0.9,
                                "p_adjusted": 1.0, "alpha": 0.01, "result": "consistent",
                                "expect": "consistent", "estimator": "plain",
                                "integrand": "genz-gaussian", "dof": 60.2, "reason": "r",
                                "mean_a": 0.5, "mean_b": 0.51, "stderr_a": 0.01,
                                "stderr_b": None, "replicates_a": 32, "replicates_b": 32,
                                "min_detectable_difference": 0.04}]
        good["runs"][0]["image"] = {"width": 4, "height": 3,
                                    "files": {"mean": "mean.exr", "stderr": "stderr.exr",
                                              "zmap": "zmap.exr", "reference": None},
                                    "rmse": None, "rel_mse": None,
                                    "pixel_test": None, "tile_test": None}
        good["runs"][0]["some_future_field"] = {"x": 1}
        errors = schema_errors(validator, good)
        check(not errors, "positive: a comparison, an image and an unknown field are accepted",
              describe(errors))

    # The semantic checks fail too.
    if b:
        bad = copy.deepcopy(b)
        bad["runs"][0]["nonfinite_fields"].remove("replicates/2/variance")
        check(any("replicates/2/variance" in p for p in semantic_problems(bad)),
              "negative: semantic check flags a null replicate variance missing from "
              "nonfinite_fields")
        bad = copy.deepcopy(b)
        bad["runs"][0]["nonfinite_fields"].append("aggregates/seconds_per_sample")
        check(any("seconds_per_sample" in p for p in semantic_problems(bad)),
              "negative: semantic check flags a nonfinite_fields entry whose value is a number")
    if a:
        check(semantic_problems(a, exit_status=1) != [],
              "negative: semantic check flags an exit status the report does not imply")

    print("%d passed, %d failed" % (checks.passed, checks.failed))
    return 1 if checks.failed else 0


if __name__ == "__main__":
    sys.exit(main())
