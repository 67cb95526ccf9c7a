#!/usr/bin/python3
"""The scene cross-check at the required power (ctest `scenes.power`, label full: ~30 min).

Usage: /usr/bin/python3 tests/scene_power_check.py PATH/TO/pcbench SOURCE_DIR

Runs `pcbench verify suites/scenes-power.json` (furnace and cornell at 128x128, each estimator
with the samples per pixel its noise needs) and checks:
  - exit 0: every tile comparison and every run as expected (honest pairs and the furnace's
    exact image consistent, the control and each 2xMDB self-check biased);
  - every honest comparison's largest detectable tile bias, relative to the tile mean on tiles
    brighter than 10% of the image mean, is at most 5%: a consistent result rules out a 5% bias
    in any bright tile, at 80% power, for every pair of estimators;
and prints each estimator's relative MSE at 1 CPU second and rays per CPU second.
"""

import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402

REQUIRED_TILE_MDB = 0.05


def main():
    binary, source = sys.argv[1:3]
    with tempfile.TemporaryDirectory() as out:
        status = subprocess.run([binary, "verify", os.path.join(source, "suites",
                                                                "scenes-power.json"),
                                 "--out", out, "--quiet"]).returncode
        check(status == 0, "verify suites/scenes-power.json exits 0", "got %d" % status)
        report = json.load(open(os.path.join(out, "report.json")))
        comparisons = report["comparisons"]
        for c in comparisons:
            check(c["result"] == c["expect"], "%s on %s: %s" % (c["estimator"], c["integrand"],
                                                                 c["result"]), c["reason"])
        honest = [c for c in comparisons if c["expect"] == "consistent"]
        check(len(honest) >= 2 * 15, "%d honest comparisons (15 pairs per scene and the "
              "furnace's exact image)" % len(honest))
        for c in honest:
            mdb = c.get("tile_relative_mdb")
            check(mdb is not None and mdb <= REQUIRED_TILE_MDB,
                  "%s on %s: detectable tile bias %.2f%% <= 5%%" % (
                      c["estimator"], c["integrand"], 100 * (mdb if mdb is not None else 1)),
                  "samples factor %s" % c.get("samples_factor_for_required_mdb"))
        for r in report["runs"]:
            image = r.get("image") or {}
            if "rel_mse_at_1_cpu_second" in image:
                print("        %-26s %-8s %5d spp: rel MSE at 1 CPU s %.3g, %.3g Mrays/CPU s" % (
                    r["estimator"], r["integrand"], r["samples"],
                    image["rel_mse_at_1_cpu_second"], image["rays_per_cpu_second"] / 1e6))
    return summary()


if __name__ == "__main__":
    sys.exit(main())
