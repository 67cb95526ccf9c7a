#!/usr/bin/python3
"""Samples per pixel for each scene run so that every block comparison meets its power requirements.

Usage: /usr/bin/python3 scripts/scene-power-budget.py PILOT_REPORT SUITE [--margin 1.5]

PILOT_REPORT is the report of `pcbench verify` on SUITE with every run at one pilot budget (the
same runs, replicates and seed, so the same Holm family and the same shares of alpha). Each
block comparison gives samples_factor_for_required_mdb, the largest over the scales with a
requirement (the suite's require_mdb: by default 8x8 tiles to 5%, the whole image to 1%) of
(relative_mdb / required_mdb)^2. The
detectable bias of a comparison goes with its standard error, whose square is the sum of the two
runs' block variances, each proportional to 1 / (samples per pixel): F_ab = v_a + v_b at the pilot
budget, F_a = v_a against an exact image. Per scene, the non-negative v_e of each estimator are
fitted to the worst case (the largest v that every comparison of e allows is not enough: v is
set so that every comparison's F is covered, v_a + v_b >= F_ab, at the smallest total). Each run
then gets pilot_samples x 2 v_e x margin samples per pixel (each run brings its half of the
variance budget down to half of the requirement), rounded up to a multiple of 10 and at least the
pilot's. Negative controls keep the suite's budget (they must be flagged, not measured).

Prints the suite with the new samples (JSON) on stdout and a table on stderr. suites/scenes-power.json
was made so: the suite with every run at 8 spp x 32 replicates (the controls at their own budget
is fine too) run by `pcbench verify PILOT.json --out PILOT`, then this script on PILOT/report.json.
"""

import argparse
import json
import math
import sys

import numpy as np


def covering_variances(estimators, factors):
    """Non-negative v_e with v_a + v_b >= F_ab (v_a >= F_a against an exact image).

    Least squares on the additive model first (each run's noise counted once, whatever its
    partner), clipped at a small floor; then every comparison the fit leaves short scales both of
    its runs up until it is covered. The model is approximate (each F is a maximum over tiles,
    and the t quantiles move with the Welch dof), which the margin absorbs.
    """
    index = {e: i for i, e in enumerate(estimators)}
    rows, rhs = [], []
    for (a, b), f in factors.items():
        row = np.zeros(len(estimators))
        row[index[a]] = 1.0
        if b is not None:
            row[index[b]] = 1.0
        rows.append(row)
        rhs.append(f)
    fit, *_ = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)
    v = {e: max(float(fit[index[e]]), 1e-3 * max(rhs)) for e in estimators}
    for _ in range(100):
        short = False
        for (a, b), f in factors.items():
            have = v[a] + (v[b] if b is not None else 0.0)
            if have < f:
                short = True
                v[a] *= f / have
                if b is not None:
                    v[b] *= f / have
        if not short:
            break
    return v


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("pilot")
    parser.add_argument("suite")
    parser.add_argument("--margin", type=float, default=1.5)
    args = parser.parse_args()
    report = json.load(open(args.pilot))
    suite = json.load(open(args.suite))
    runs = {r["id"]: r for r in report["runs"]}
    # The runs of the honest comparisons (negative controls may keep their own budget).
    fitted = {c[k] for c in report["comparisons"] if c["test"] == "block-pyramid"
              and c["expect"] == "consistent" for k in ("a", "b") if c[k] in runs}
    pilot_samples = {runs[i]["samples"] for i in fitted}
    if len(pilot_samples) != 1:
        sys.exit("scene-power-budget: the pilot's honest runs must share one budget")
    pilot = pilot_samples.pop()

    scenes = {}
    for c in report["comparisons"]:
        if c["test"] != "block-pyramid" or c["a"].endswith("+injected"):
            continue
        if c["expect"] != "consistent":
            continue
        a = runs[c["a"]]["estimator"]
        b = None if c["b"] == "exact" else runs[c["b"]]["estimator"]
        factor = c.get("samples_factor_for_required_mdb")
        if factor is None:
            sys.exit(f"scene-power-budget: {c['estimator']} on {c['integrand']} has no factor")
        scenes.setdefault(c["integrand"], {})[(a, b)] = factor

    budget = {}
    for scene, factors in scenes.items():
        estimators = sorted({e for pair in factors for e in pair if e is not None})
        v = covering_variances(estimators, factors)
        for e in estimators:
            need = pilot * 2 * v[e] * args.margin
            budget[(e, scene)] = max(pilot, int(math.ceil(need / 10.0)) * 10)
        worst = max(factors.items(), key=lambda kv: kv[1])
        print(f"{scene}: worst pilot factor {worst[1]:.3g} ({worst[0][0]} vs "
              f"{worst[0][1] or 'exact'})", file=sys.stderr)

    for run in suite["runs"]:
        key = (run["estimator"], run["integrand"])
        if key in budget:
            run["samples"] = budget[key]
        print(f"  {run['estimator']:<26} {run['integrand']:<10} {run['samples']:>6} spp",
              file=sys.stderr)
    # One run a line, as the suite files are written.
    head = {k: v for k, v in suite.items() if k != "runs"}
    lines = [f"  {json.dumps(k)}: {json.dumps(v, ensure_ascii=False)}," for k, v in head.items()]
    runs_text = ",\n".join("    " + json.dumps(r) for r in suite["runs"])
    print("{\n" + "\n".join(lines) + '\n  "runs": [\n' + runs_text + "\n  ]\n}")


if __name__ == "__main__":
    main()
