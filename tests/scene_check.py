#!/usr/bin/python3
"""The scene cross-check: every estimator against every other on built-in scenes, per 8x8 tile.

Usage (ctest `scenes.small`, label ci, and `scenes.full`, label full):
    /usr/bin/python3 tests/scene_check.py PATH/TO/pcbench SOURCE_DIR RESOLUTION SAMPLES REPLICATES
                     [--report-power] [--reference-cache DIR] [--skip-scene NAME]

Runs `pcbench verify` on suites/scenes.json (rewritten to RESOLUTION, SAMPLES per pixel and
REPLICATES): path tracing, light tracing, BDPT (plain), vertex connection, the light vertex
cache, probabilistic connections, ris and restir on furnace, cornell, cornell-glossy, door-ajar and lampshade
(less any --skip-scene), and the scene negative controls where their flaw shows; then checks the
report:
  - exit 0: every tile comparison came out as expected (honest pairs consistent, every pair with
    a control biased, the furnace consistent with its exact image, each 2xMDB self-check biased);
  - each scene negative control is flagged by every honest estimator;
  - EXR files exist and `exrheader` reads 32-bit float channels;
  - the counters show what was skipped: no shadow ray in the (convex) furnace, no light paths
    for path tracing, one BVH per scene for all runs; door-ajar's BDPT connections are mostly
    occluded; on lampshade most of path tracing's shadow rays are occluded and fewer than half
    of BDPT's connections carry light (the rest are occluded or have a zero value);
  - with --report-power, each scene's worst honest comparison's detectable tile bias (relative
    to the tile mean, on tiles brighter than 10% of the image mean) is printed against the
    requirement of 5%. It is printed, not asserted here: at one budget for every estimator it is
    met on the furnace only; tests/scene_power_check.py (scenes.power) asserts it on furnace and
    cornell with the budgets of suites/scenes-power.json; door-ajar needs 300-3600 times 16 spp;
  - with --reference-cache DIR, the equal-time errors it prints are measured against DIR's
    converged images (`pcbench reference`) where it has them.
Prints one line per check and "N passed, M failed"; exits 1 if any check failed.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile

HONEST = ["plain", "pt", "lt", "vc-all", "lvc", "pcbpt", "ris", "restir"]
SCENES = ["furnace", "cornell", "cornell-glossy", "door-ajar", "lampshade"]
# Where each control's flaw shows (in a convex furnace every cache point sees every light vertex,
# so the visible-only importance is honest there).
CONTROLS = {"ctl-scene-visible-only": ["door-ajar"],
            "ctl-scene-lvc-per-vertex": ["furnace", "cornell", "door-ajar"],
            "ctl-scene-naive-reuse": ["cornell"]}
REQUIRED_TILE_MDB = 0.05


def main():
    binary, source, resolution, samples, replicates = sys.argv[1:6]
    power = "--report-power" in sys.argv[6:]
    # Converged images for the equal-time errors (pcbench reference); the tests never use them.
    reference_cache = []
    if "--reference-cache" in sys.argv[6:]:
        reference_cache = ["--reference-cache",
                           sys.argv[sys.argv.index("--reference-cache") + 1]]
    skipped = [sys.argv[i + 1] for i, a in enumerate(sys.argv) if a == "--skip-scene"]
    scenes = [s for s in SCENES if s not in skipped]
    passed = failed = 0

    def check(ok, what):
        nonlocal passed, failed
        print(("ok      " if ok else "FAILED  ") + what)
        passed += bool(ok)
        failed += not ok

    with tempfile.TemporaryDirectory() as out:
        suite = json.load(open(os.path.join(source, "suites", "scenes.json")))
        for row in suite["grid"]:
            row["params"]["resolution"] = [resolution]
            row["integrand"] = [i for i in row["integrand"] if i not in skipped]
        suite_path = os.path.join(out, "scenes.json")
        json.dump(suite, open(suite_path, "w"))
        args = [binary, "verify", suite_path, "-n", samples, "-r", replicates,
                "--out", out, "--quiet"] + reference_cache
        status = subprocess.run(args).returncode
        check(status == 0, "verify suites/scenes.json at %s, %s spp x %s replicates exits 0 "
              "(got %d)" % (resolution, samples, replicates, status))
        report = json.load(open(os.path.join(out, "report.json")))
        runs = {r["id"]: r for r in report["runs"]}
        comparisons = report["comparisons"]

        for c in comparisons:
            if c["result"] != c["expect"]:
                check(False, "%s on %s: %s (expected %s): %s" % (
                    c["estimator"], c["integrand"], c["result"], c["expect"], c["reason"]))
        check(all(c["result"] == c["expect"] for c in comparisons),
              "all %d tile comparisons as expected" % len(comparisons))

        for scene in scenes:
            on_scene = [c for c in comparisons if c["integrand"] == scene]
            for control, where in sorted(CONTROLS.items()):
                if scene not in where:
                    continue
                flagged = [c for c in on_scene if control in c["estimator"] and
                           c["result"] == "biased"]
                honest_runs = [r for r in runs.values() if r["integrand"] == scene and
                               r["estimator"] in HONEST]
                check(len(flagged) == len(honest_runs) or
                      (scene == "furnace" and len(flagged) >= 1),
                      "%s on %s flagged by %d of %d honest runs" % (
                          control, scene, len(flagged), len(honest_runs)))
            injected = [c for c in on_scene if c["a"].endswith("+injected")]
            scales = len(injected[0]["scales"]) if injected else 0
            check(len(injected) == scales and scales > 0 and
                  all(c["result"] == "biased" for c in injected),
                  "%s: a bias of 2x the reported MDB in one block of each of the %d scales is "
                  "flagged" % (scene, scales))
            if power:
                honest = [c for c in on_scene if c["expect"] == "consistent" and
                          not c["a"].endswith("+injected") and
                          c.get("tile_relative_mdb") is not None]
                if honest:
                    worst = max(honest, key=lambda c: c["tile_relative_mdb"])
                    print("        %s: largest detectable tile bias %.2f%% (%s); requirement 5%%: "
                          "%s" % (scene, 100 * worst["tile_relative_mdb"], worst["estimator"],
                                  "met" if worst["tile_relative_mdb"] <= REQUIRED_TILE_MDB
                                  else "NOT met"))

        def counters(estimator, scene):
            for r in runs.values():
                if r["estimator"] == estimator and r["integrand"] == scene:
                    return r["counters"]
            return None

        furnace = counters("plain", "furnace")
        check(furnace["shadow_rays"] == 0 and furnace["skipped_convex_enclosure"] > 0,
              "furnace (a convex enclosure): no shadow rays, %d connections skipped the test" %
              furnace["skipped_convex_enclosure"])
        check(counters("pt", "cornell")["light_paths"] == 0,
              "path tracing traces no light pool")
        builds = max(r["counters"]["scene_builds"] for r in runs.values())
        check(builds == len(scenes), "%d BVH builds for %d scenes and %d runs" %
              (builds, len(scenes), len(runs)))
        door = counters("plain", "door-ajar")
        share = door["occluded"] / max(1, door["shadow_rays"])
        check(share > 0.5, "door-ajar: %.1f%% of BDPT's shadow rays are occluded" % (100 * share))
        if "lampshade" in scenes:
            nee = counters("pt", "lampshade")
            share = nee["occluded"] / max(1, nee["shadow_rays"])
            check(share > 0.5, "lampshade: %.1f%% of path tracing's shadow rays are occluded" %
                  (100 * share))
            bdpt = counters("plain", "lampshade")
            carry = (bdpt["shadow_rays"] - bdpt["occluded"]) / max(1, bdpt["connections"])
            check(carry < 0.5, "lampshade: %.1f%% of BDPT's connections carry light" % (100 * carry))

        exrheader = shutil.which("exrheader")
        some = next(r for r in runs.values() if r.get("image"))
        path = os.path.join(out, some["image"]["files"]["mean"])
        check(os.path.exists(path), "EXR written: " + some["image"]["files"]["mean"])
        if exrheader:
            text = subprocess.run([exrheader, path], capture_output=True, text=True).stdout
            check("32-bit floating-point" in text, "exrheader reads 32-bit float channels")
        for r in runs.values():
            if r["estimator"] in CONTROLS or r["integrand"] == "furnace":
                continue
            image = r.get("image") or {}
            if image.get("reference", "none") != "none":
                print("        %-24s %-15s rel MSE at 1 CPU s %.3g, %.3g Mrays/CPU s" % (
                    r["estimator"], r["integrand"], image["rel_mse_at_1_cpu_second"],
                    image["rays_per_cpu_second"] / 1e6))

    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
