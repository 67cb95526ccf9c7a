#!/usr/bin/python3
"""Usage: scripts/equal_time_images.py --reference REF.exr [--baseline NAME] [--per-replicate CSV]
          NAME=SOURCE [NAME=SOURCE ...]

Relative MSE × CPU seconds per replicate (lower is better) of sets of replicate images from any
renderers, and each set's ratio to the baseline set's (default: the first) with a 95% interval.
A SOURCE is
  - a glob of pcbench report.json files (quote it): the replicate images of their scene runs made
    with --replicate-images, with each replicate's `cpu_seconds` (process CPU); runs of estimator
    NAME if the reports hold any, else every run;
  - a CSV with columns file, spp, cpu_seconds (scripts/blender_render_cpu.py's cpu-<N>.csv);
    a cpu_seconds of nan gives the set's error alone.
REF.exr is a converged image: channels R, G, B, and its standard error stderr.R, .G, .B if it has
them (a `pcbench reference` cache entry, results/references/<scene>-<key>.exr).

Per set it prints the replicates, spp, relative MSE per replicate against REF — the mean over
values of (x − ref)² / scale², scale = ref + 1% of ref's mean, less REF's own relative variance
(mean of (stderr / scale)²), as harness/verify/image_errors.cpp computes `rel_mse_per_replicate`
— the replicates' own relative variance about their mean (the same without REF: the two differ
by the set's squared bias against REF, and by noise), CPU s per replicate, relative MSE × CPU s
(pcbench's `rel_mse_at_1_cpu_second`: mean relative MSE × mean CPU) and its ratio to the
baseline's, then that ratio's two factors: error per sample (relative MSE × spp) and cost per
sample (µs per pixel sample: CPU / (W × H × spp)), each ÷ the baseline's. Intervals are 95%
percentile bootstraps, 10000 resamples of each set's replicates, independently per set.
--per-replicate writes every replicate's row (set, file, relative MSE, CPU s, product).
"""
import argparse
import csv
import glob
import json
import math
import os
import sys

import numpy as np
import OpenImageIO as oiio

FLOOR = 0.01  # harness/verify/image_statistics.h, kRelativeErrorFloor


def read_channels(path, names):
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit(f"equal_time_images: cannot read {path}: {oiio.geterror()}")
    channels = list(image.spec().channelnames)
    pixels = image.read_image(format="float").astype(np.float64)
    image.close()
    if not all(n in channels for n in names):
        return None
    return np.stack([pixels[:, :, channels.index(n)] for n in names], -1)


def from_reports(name, pattern):
    """[(file, cpu_seconds, spp)] of the replicate images of the runs in the reports."""
    rows = []
    for path in sorted(glob.glob(pattern)):
        runs = [r for r in json.load(open(path))["runs"]
                if (r.get("image") or {}).get("files", {}).get("replicates")]
        mine = [r for r in runs if r["estimator"] == name] or runs
        for run in mine:
            files = run["image"]["files"]["replicates"]
            for file, replicate in zip(files, run["replicates"]):
                rows.append((os.path.join(os.path.dirname(path), file), replicate["cpu_seconds"],
                             run["samples"]))
    return rows


def from_csv(path):
    return [(row["file"], float(row["cpu_seconds"]), int(row["spp"]))
            for row in csv.DictReader(open(path))]


def load(name, source, reference, scale, own):
    rows = from_csv(source) if source.endswith(".csv") else from_reports(name, source)
    if len(rows) < 2:
        sys.exit(f"equal_time_images: {name}: {len(rows)} replicate(s) in {source}")
    images = np.array([read_channels(f, ["R", "G", "B"]) for f, _, _ in rows])
    if images.shape[1:] != reference.shape:
        sys.exit(f"equal_time_images: {name}: images {images.shape[1:]}, reference "
                 f"{reference.shape}")
    errors = np.mean((images - reference)**2 / scale**2, axis=(1, 2, 3)) - own
    spread = float(np.mean(images.var(0, ddof=1) / scale**2))
    cpu = np.array([c for _, c, _ in rows])
    spp = {s for _, _, s in rows}
    if len(spp) != 1:
        sys.exit(f"equal_time_images: {name}: replicates of different spp {sorted(spp)}")
    return {"files": [f for f, _, _ in rows], "errors": errors, "cpu": cpu, "spread": spread,
            "spp": spp.pop()}


def bootstrap(s, rng, count=10000):
    """Resampled means of relative MSE × spp and of CPU s / spp (error and cost per sample)."""
    n = len(s["errors"])
    picks = rng.integers(0, n, (count, n))
    return s["errors"][picks].mean(1) * s["spp"], s["cpu"][picks].mean(1) / s["spp"]


def interval(draws, name, baseline, f):
    """f(name's figures) / f(baseline's figures): its 95% percentile interval, as text."""
    low, high = np.percentile(f(*draws[name]) / f(*draws[baseline]), [2.5, 97.5])
    return f"{low:.3f}–{high:.3f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", required=True)
    parser.add_argument("--baseline")
    parser.add_argument("--per-replicate")
    parser.add_argument("sets", nargs="+", metavar="NAME=SOURCE")
    args = parser.parse_args()
    reference = read_channels(args.reference, ["R", "G", "B"])
    stderr = read_channels(args.reference, ["stderr.R", "stderr.G", "stderr.B"])
    scale = reference + FLOOR * reference.mean()
    own = float(np.mean((stderr / scale)**2)) if stderr is not None else 0.0
    sets = {}
    for item in args.sets:
        name, _, source = item.partition("=")
        sets[name] = load(name, source, reference, scale, own)
    baseline = args.baseline or next(iter(sets))
    rng = np.random.default_rng(1)
    draws = {name: bootstrap(s, rng) for name, s in sets.items()}
    pixels = reference.shape[0] * reference.shape[1]
    print(f"reference {args.reference}: own relative variance {own:.3g} (taken off), "
          f"scale = ref + {FLOOR:g} × {reference.mean():.4g}")
    print()
    print(f"| set | replicates | spp | rel MSE | rel variance | CPU s | rel MSE × CPU s | "
          f"÷ {baseline} (95%) | error/sample ÷ {baseline} | µs/sample | ÷ {baseline} |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    base = sets[baseline]
    base_error, base_cost = base["errors"].mean() * base["spp"], base["cpu"].mean() / base["spp"]
    for name, s in sets.items():
        e, c = float(s["errors"].mean()), float(s["cpu"].mean())
        error, cost = e * s["spp"], c / s["spp"]
        timed = np.isfinite(s["cpu"]).all() and np.isfinite(base["cpu"]).all()
        cells = [f"`{name}`", f"{len(s['errors'])}", f"{s['spp']}", f"{e:.4g}",
                 f"{s['spread']:.4g}"]
        if timed:
            product = interval(draws, name, baseline, lambda a, b: a * b)
            cells += [f"{c:.3f}", f"{e * c:.4g}",
                      f"{error * cost / (base_error * base_cost):.3f} ({product})"]
        else:
            cells += ["—", "—", "—"]
        per_sample = interval(draws, name, baseline, lambda a, b: a)
        cells.append(f"{error / base_error:.3f} ({per_sample})")
        if timed:
            per_cost = interval(draws, name, baseline, lambda a, b: b)
            cells += [f"{cost / pixels * 1e6:.4f}", f"{cost / base_cost:.3f} ({per_cost})"]
        else:
            cells += ["—", "—"]
        print("| " + " | ".join(cells) + " |")
    if args.per_replicate:
        with open(args.per_replicate, "w") as out:
            out.write("set,file,rel_mse,cpu_seconds,product\n")
            for name, s in sets.items():
                for f, e, c in zip(s["files"], s["errors"], s["cpu"]):
                    product = e * c if math.isfinite(c) else float("nan")
                    out.write(f"{name},{f},{e:.6g},{c:.6f},{product:.6g}\n")


if __name__ == "__main__":
    main()
