#!/usr/bin/python3
"""Usage: scripts/relative_mse_table.py OUT [CHECKPOINTS] [SCENE ...]

The equal-time tables of docs/findings/pcbpt-equal-time.md from a finished scene session in folder OUT (its report.json and
checkpoint/): for each run, the report's relative MSE at 1 CPU s against the cached reference
(`image.rel_mse_at_1_cpu_second` = relative MSE per replicate × CPU s per replicate, net of the
reference's own variance; run `pcbench reference` for the scenes first, or the figure is against
the best-converged honest run, as `image.reference` says) and its ratio to BDPT (`plain`).
± is the jackknife over replicates of the per-replicate relative variance (per value, scale = the
scene's pooled mean over runs + 1% of its mean, as harness/verify/image_statistics.cpp scales)
× CPU s, applied as a relative uncertainty to the report's figure. A row's label is the estimator
and the parameters in which it differs from that estimator's first run in the report. A second
table gives, per scene, what a replicate costs: relative MSE per replicate, CPU s, shadow rays
(connections' and, for pcbpt, the cache points' visibility) and their occluded share.
A finished session deletes OUT/checkpoint: copy it while the session runs and name the copy as
CHECKPOINTS (a run without its checkpoint gets no ±)."""
import json
import os
import sys

import numpy as np

folder = sys.argv[1]
report = json.load(open(os.path.join(folder, "report.json")))
runs = [r for r in report["runs"] if r.get("image")]
rest = sys.argv[2:]
checkpoints = os.path.join(folder, "checkpoint")
if rest and os.path.isdir(rest[0]):
    checkpoints = rest.pop(0)
scenes = rest or list(dict.fromkeys(r["integrand"] for r in runs))
IGNORED = {"resolution", "max_length"}

first_params = {}
for r in runs:
    first_params.setdefault(r["estimator"], r["params"])


def label(run):
    base = first_params[run["estimator"]]
    diff = [f"{k}={v}" for k, v in run["params"].items()
            if k not in IGNORED and base.get(k) != v]
    return " ".join([run["estimator"]] + diff)


def checkpoint(run):
    path = os.path.join(checkpoints, run["id"] + ".json")
    if not os.path.exists(path):
        return None
    saved = json.load(open(path))["result"]
    images = np.array([image["values"] for image in saved["images"]])
    cpu = np.array([replicate["cpu_seconds"] for replicate in saved["replicates"]])
    return images, cpu


data = {r["id"]: checkpoint(r) for r in runs}
pooled = {}
for r in runs:
    if data[r["id"]] is not None:
        pooled.setdefault(r["integrand"], []).append(data[r["id"]][0].mean(0))


def relative_spread(run):
    if data[run["id"]] is None:
        return None
    images, cpu = data[run["id"]]
    reference = np.mean(pooled[run["integrand"]], 0)
    scale = reference + 0.01 * reference.mean()

    def at_one_second(keep):
        return float(np.mean(images[keep].var(0, ddof=1) / scale**2)) * cpu[keep].mean()
    count = len(images)
    full = at_one_second(np.arange(count))
    jackknife = np.array([at_one_second(np.delete(np.arange(count), k)) for k in range(count)])
    se = float(np.sqrt((count - 1) / count * np.sum((jackknife - jackknife.mean())**2)))
    return se / full if full > 0 else 0.0


bdpt = {r["integrand"]: r["image"]["rel_mse_at_1_cpu_second"] for r in runs
        if r["estimator"] == "plain" and label(r) == "plain"}
rows = list(dict.fromkeys(label(r) for r in runs))
print("| estimator | " + " | ".join(scenes) + " |")
print("|---|" + "---|" * len(scenes))
for row in rows:
    cells = []
    for scene in scenes:
        match = [r for r in runs if label(r) == row and r["integrand"] == scene]
        if not match:
            cells.append("—")
            continue
        r = match[0]
        figure = r["image"]["rel_mse_at_1_cpu_second"]
        ratio = f" ({figure / bdpt[scene]:.2f}×)" if scene in bdpt else ""
        spread = relative_spread(r)
        plus_minus = f" ± {figure * spread:.2g}" if spread is not None else ""
        cells.append(f"{figure:.3g}{plus_minus}{ratio}")
    print(f"| `{row}` | " + " | ".join(cells) + " |")
print()
references = sorted({f"{r['integrand']}: {r['image'].get('reference')}" for r in runs})
print("references: " + ", ".join(references))
for scene in scenes:
    print()
    print(f"{scene}, per replicate | rel MSE | CPU s | shadow rays | occluded |")
    print("|---|---|---|---|---|")
    for row in rows:
        match = [r for r in runs if label(r) == row and r["integrand"] == scene]
        if not match:
            continue
        r = match[0]
        image, counters = r["image"], r["counters"]
        replicates = r["replicates_requested"]
        rays = counters.get("shadow_rays", 0)
        occluded = counters.get("occluded", 0) / rays if rays else 0.0
        print(f"| `{row}` | {image['rel_mse_per_replicate']:.3g} | "
              f"{image['cpu_seconds_per_replicate']:.3g} | {rays / replicates / 1e6:.2f} M | "
              f"{occluded:.1%} |")
