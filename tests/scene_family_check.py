#!/usr/bin/python3
"""The scene tile tests keep their power promise at the threshold that decides, and a scene
negative control alone is caught (issue 19's reproductions).

Usage (ctest `scenes.family`, label ci):
    /usr/bin/python3 tests/scene_family_check.py PATH/TO/pcbench

1. Five honest estimators on five scenes at 32x32, 4 spp x 4 replicates, seed 3: a small
   replicate count, where Student quantiles grow fast, in a family of 65 tested verdicts (with
   lampshade: its CI check, which scenes.small leaves out). The detectable tile bias used to be computed at alpha / T of the comparison alone, so the
   self-checks' "2xMDB injected" comparisons were not flagged once the session's Holm family
   adjusted them again (exit 1). Now every tile comparison states its per-tile share
   alpha / (m T), m the session's tested verdicts, and the run exits 0.
2. `verify -e CONTROL` for each scene control (the visible-only one also with
   `-p design=published`): it renders the control and its declared honest
   partner (plain, or pt for the reuse controls), the tile comparison flags the control, exit 0.
Prints one line per check and "N passed, M failed"; exits 1 if any check failed.
"""

import json
import os
import subprocess
import sys
import tempfile

ALPHA = 0.01
TILE_TESTS_32 = 16 * 3  # 4x4 tiles of 8x8 pixels, 3 channels
SCENES = ["furnace", "cornell", "cornell-glossy", "door-ajar", "lampshade"]
# (control, its scene, extra parameters, its declared honest partner): the visible-only control
# in pcbpt's legacy tile design and in the published one (zero visibility floor, no mixing); the
# reuse controls against path tracing.
CONTROLS = [("ctl-scene-visible-only", "door-ajar", [], "plain"),
            ("ctl-scene-visible-only", "door-ajar", ["-p", "design=published"], "plain"),
            ("ctl-scene-lvc-per-vertex", "cornell", [], "plain"),
            ("ctl-scene-nee-count", "cornell", [], "plain"),
            ("ctl-scene-naive-reuse", "cornell", [], "pt"),
            ("ctl-scene-reuse-unshadowed", "cornell", [], "pt")]

passed = 0
failed = 0


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
    print(("ok   " if ok else "FAIL ") + what)


def run(pcbench, args, out):
    proc = subprocess.run([pcbench] + args + ["-q", "--out", out], capture_output=True, text=True)
    report = None
    path = os.path.join(out, "report.json")
    if os.path.exists(path):
        with open(path) as f:
            report = json.load(f)
    return proc, report


def tested_verdicts(report):
    runs = sum(1 for r in report["runs"] if r.get("verdict") and r["verdict"]["test"] != "none")
    comparisons = sum(1 for c in report["comparisons"] if c["test"] != "none")
    return runs + comparisons


def family_power(pcbench, folder):
    proc, report = run(pcbench, ["run", "-e", "pt,lt,plain,vc-all,lvc", "-i", ",".join(SCENES),
                                 "-p", "resolution=32",
                                 "-n", "4", "-r", "4", "--seed", "3"], folder)
    check(proc.returncode == 0, f"the reproduction exits 0 (got {proc.returncode}: "
          f"{proc.stderr.strip()[-300:]})")
    if report is None:
        check(False, "the reproduction wrote a report")
        return
    m = tested_verdicts(report)
    tiles = [c for c in report["comparisons"] if c["test"] == "block-pyramid"]
    # 32x32 images: a pyramid of blocks of 8, 16 and 32 pixels (48, 12 and 3 tests); each scale's
    # share is alpha / (m L n_s).
    scales = [(8, TILE_TESTS_32), (16, 12), (32, 3)]
    check(len(tiles) > 0 and all(
        [(s["block"], s["tests"]) for s in c["scales"]] == scales and
        all(abs(s["alpha_share"] - ALPHA / (m * 3 * n)) <= 1e-12 * ALPHA / (m * 3 * n)
            for s, (_, n) in zip(c["scales"], scales)) and
        c["tile_alpha_share"] == c["scales"][0]["alpha_share"] for c in tiles),
          f"all {len(tiles)} block comparisons test scales {scales} and state each scale's "
          f"share alpha / (m L n_s) = {ALPHA} / ({m} x 3 x n_s)")
    injected = [c for c in tiles if c["a"].endswith("+injected")]
    check(len(injected) == 3 * len(SCENES),
          f"one 2xMDB self-check per scene and scale ({len(injected)})")
    for c in injected:
        check(c["result"] == "biased",
              f"{c['integrand']}: {c['estimator']} flagged (family-adjusted p = "
              f"{c['p_adjusted']:.3g})")
    honest = [c for c in tiles if not c["a"].endswith("+injected")]
    wrong = [c["estimator"] + " on " + c["integrand"] for c in honest if c["result"] != c["expect"]]
    check(not wrong, f"every honest tile comparison as expected ({len(honest)}; wrong: {wrong})")


def controls_alone(pcbench, folder):
    for n, (control, scene, extra, partner) in enumerate(CONTROLS):
        out = os.path.join(folder, f"{control}-{n}")
        proc, report = run(pcbench, ["verify", "-e", control] + extra, out)
        check(proc.returncode == 0,
              f"verify -e {control} {' '.join(extra)} exits 0 (got {proc.returncode})")
        if report is None:
            check(False, f"{control} wrote a report")
            continue
        estimators = [r["estimator"] for r in report["runs"]]
        check(estimators == [control, partner] and
              all(r["integrand"] == scene for r in report["runs"]),
              f"{control} ran with its partner on {scene}: {estimators}")
        caught = [c for c in report["comparisons"]
                  if c["test"] == "block-pyramid" and control in c["estimator"]]
        check(len(caught) == 1 and caught[0]["result"] == "biased" and
              caught[0]["expect"] == "biased",
              f"{control} flagged by the tile comparison with {partner} "
              f"({[c['result'] for c in caught]})")


def main():
    pcbench = sys.argv[1]
    with tempfile.TemporaryDirectory() as folder:
        family_power(pcbench, os.path.join(folder, "family"))
        controls_alone(pcbench, folder)
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
