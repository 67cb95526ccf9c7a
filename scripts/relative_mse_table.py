#!/usr/bin/python3
"""Usage: scripts/relative_mse_table.py OUT/checkpoint SUITE.json

Relative MSE at 1 CPU s per run of a scene suite from its session's checkpoints (plan
order = completion order: rows, then estimators, then integrands). For unbiased estimators the
per-replicate relative MSE is the per-replicate relative variance: mean over values of the
replicates' sample variance / scale², scale = pooled mean of the scene's first-row runs + 1% of
its mean (harness/verify/image_statistics.cpp relative_error_scale). ± is a jackknife over replicates."""
import json
import os
import sys

import numpy as np
folder = sys.argv[1]
suite = json.load(open(sys.argv[2]))
labels = []
for row in suite["grid"]:
    extra = " ".join(f"{k}={v[0]}" for k, v in row["params"].items() if k != "resolution")
    for e in row["estimator"]:
        for i in row["integrand"]:
            labels.append((e + (" " + extra if extra else ""), i))
files = sorted((f for f in os.listdir(folder) if f.endswith(".json") and f != "session.json"),
               key=lambda f: os.path.getmtime(os.path.join(folder, f)))
runs = []
for (label, scene), f in zip(labels, files):
    r = json.load(open(os.path.join(folder, f)))["result"]
    imgs = np.array([im["values"] for im in r["images"]])
    cpu = np.array([x["cpu_seconds"] for x in r["replicates"]])
    sc = r.get("scene_counters") or []
    runs.append(dict(label=label, scene=scene, imgs=imgs, cpu=cpu, counters=r["counters"], sc=sc))
pooled = {}
for run in runs:
    if " " not in run["label"]:
        pooled.setdefault(run["scene"], []).append(run["imgs"].mean(0))
def relvar(imgs, scale):
    return float(np.mean(imgs.var(0, ddof=1) / scale**2))
for run in runs:
    ref = np.mean(pooled[run["scene"]], 0)
    scale = ref + 0.01 * ref.mean()
    R = len(run["imgs"])
    full = relvar(run["imgs"], scale) * run["cpu"].mean()
    jk = [relvar(np.delete(run["imgs"], k, 0), scale) * np.delete(run["cpu"], k).mean() for k in range(R)]
    se = float(np.sqrt((R - 1) / R * np.sum((np.array(jk) - np.mean(jk))**2)))
    run["at1"], run["se"] = full, se
scenes = ["door-ajar", "cornell", "cornell-glossy"]
plain = {r["scene"]: r["at1"] for r in runs if r["label"] == "plain"}
print("| estimator | " + " | ".join(scenes) + " | door-ajar: rel MSE per replicate | CPU s per replicate | shadow rays per replicate |")
print("|---|" + "---|" * (len(scenes) + 3))
for label in dict.fromkeys(r["label"] for r in runs):
    cells = []
    extra = ["", ""]
    for s in scenes:
        m = [r for r in runs if r["label"] == label and r["scene"] == s]
        if not m: cells.append("—"); continue
        r = m[0]
        ratio = f" ({r['at1']/plain[s]:.2f}×)" if s in plain else ""
        cells.append(f"{r['at1']:.3g} ± {r['se']:.2g}{ratio}")
        if s == "door-ajar":
            sc = dict(r["sc"])
            extra = [f"{r['at1'] / r['cpu'].mean():.3g}", f"{r['cpu'].mean():.2f}",
                     f"{sc.get('shadow_rays', 0) / len(r['cpu']) / 1e6:.2f} M"]
    print(f"| `{label}` | " + " | ".join(cells) + " | " + " | ".join(extra) + " |")
