#!/usr/bin/python3
"""What paired streams buy: each scene's block pyramids run twice, with independent streams and
with --paired, and the detectable bias per pair and scale side by side.

Usage:
    /usr/bin/python3 scripts/paired-gain.py PCBENCH OUT_DIR [--estimators pt,plain,...]
        [--scenes cornell,...] [--seeds 1,2,3] [RUN OPTIONS...]

RUN OPTIONS go to `pcbench run` as given (for example -p resolution=64 -n 4 -r 16 -t 2). For
every scene and seed, `pcbench run -e ESTIMATORS -i SCENE -s SEED RUN OPTIONS -q --out
OUT_DIR/SCENE-SEED-own` and the same with --paired into OUT_DIR/SCENE-SEED-paired; then one
markdown row per compared pair: the relative detectable bias (relative_mdb) of the tiles and of
the whole image in both designs (medians over the seeds), and how many times the samples the
independent design would need to match the paired one at each of those scales, (own /
paired)^2, as the geometric mean over the seeds (one seed's ratio is noisy: 16 replicates give
each standard error to about ±18%). Exits 1 if a run fails to write its report.
"""

import math
import statistics

import json
import os
import subprocess
import sys


def option(args, name, default):
    if name in args:
        i = args.index(name)
        value = args[i + 1]
        del args[i:i + 2]
        return value.split(",")
    return default


def percent(fraction):
    return f"{100.0 * fraction:.3g}%"


def pyramids(report):
    """{estimator pair: comparison} of a report's block pyramids, self-checks left out."""
    return {c["estimator"]: c for c in report["comparisons"]
            if c["test"] == "block-pyramid" and not c["a"].endswith("+injected")
            and c["b"] != "exact"}


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    pcbench, out = args[0], args[1]
    rest = args[2:]
    estimators = option(rest, "--estimators", ["pt", "plain", "lvc", "vc-all", "pcbpt"])
    scenes = option(rest, "--scenes", ["cornell"])
    seeds = option(rest, "--seeds", ["1"])
    print("| scene | pair | 8 px own | 8 px paired | samples ratio, 8 px | image own | "
          "image paired | samples ratio, image |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        # mdb[pair][design][scale] = one relative_mdb per seed
        mdb = {}
        for seed in seeds:
            for design in ("own", "paired"):
                folder = os.path.join(out, f"{scene}-{seed}-{design}")
                command = [pcbench, "run", "-e", ",".join(estimators), "-i", scene, "-s", seed,
                           *rest, "-q", "--out", folder]
                if design == "paired":
                    command.append("--paired")
                subprocess.run(command, stdout=subprocess.DEVNULL)
                path = os.path.join(folder, "report.json")
                if not os.path.exists(path):
                    sys.exit(f"paired-gain: {' '.join(command)} wrote no report")
                with open(path) as f:
                    for pair, c in pyramids(json.load(f)).items():
                        entry = mdb.setdefault(pair, {"own": ([], []), "paired": ([], [])})
                        entry[design][0].append(c["scales"][0]["relative_mdb"])
                        entry[design][1].append(c["scales"][-1]["relative_mdb"])

        def ratio(entry, scale):
            logs = [2.0 * math.log(o / p)
                    for o, p in zip(entry["own"][scale], entry["paired"][scale])]
            return math.exp(statistics.fmean(logs))

        for pair, entry in mdb.items():
            med = {d: [statistics.median(entry[d][s]) for s in (0, 1)] for d in entry}
            print(f"| {scene} | {pair} | {percent(med['own'][0])} | {percent(med['paired'][0])} | "
                  f"{ratio(entry, 0):.3g}× | {percent(med['own'][1])} | "
                  f"{percent(med['paired'][1])} | {ratio(entry, 1):.3g}× |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
