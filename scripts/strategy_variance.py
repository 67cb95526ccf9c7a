#!/usr/bin/python3
"""Usage: scripts/strategy_variance.py [--top N] OUT [OUT ...]

Where an estimator's variance lies, strategy by strategy. Each OUT is a session folder of the
same runs with a different seed, made with --strategy-images, for instance

    for s in 1 2 3 4 5 6 7 8; do
      build/release/pcbench run -e plain,pcbpt -i door-ajar -p resolution=64 -n 8 -r 2 \\
        --strategy-images --seed $s --quiet --out results/strategies/s$s
    done
    scripts/strategy_variance.py results/strategies/s*

A run's images/<id>_strategies.exr holds the mean image of each (s, t) strategy (results/
strategy_images.h); its id does not depend on the seed, so the folders give independent draws of
every layer. Per run (estimator and its parameters), the script prints the relative variance of
the run's mean image across the folders, mean over values of Var / scale² with scale = the
scene's mean image over all runs and folders + 1% of its mean (as
harness/verify/image_statistics.cpp scales relative errors), and the N strategies with the
largest such variance, each with its share of that total and of the image's mean. The layers'
variances need not add up to the total: the strategies of one run are correlated (they share
its light pool and camera paths)."""
import json
import os
import sys

import numpy as np
import OpenImageIO as oiio


def read_layers(path):
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit(f"strategy_variance: cannot read {path}: {oiio.geterror()}")
    names = list(image.spec().channelnames)
    pixels = image.read_image(format="float")
    image.close()
    layers = {}
    for channel, name in enumerate(names):
        layer, colour = name.rsplit(".", 1)
        layers.setdefault(layer, {})[colour] = pixels[:, :, channel].astype(np.float64)
    return {name: np.stack([c["R"], c["G"], c["B"]], -1) for name, c in layers.items()}


def run_label(run):
    params = " ".join(f"{k}={v}" for k, v in run["params"].items() if k != "resolution")
    return f"{run['estimator']} on {run['integrand']} {params}"


def main(argv):
    top = 8
    if argv[:1] == ["--top"]:
        top, argv = int(argv[1]), argv[2:]
    if len(argv) < 2:
        sys.exit(__doc__)
    runs = {}  # label -> (integrand, [layers per folder])
    for folder in argv:
        report = json.load(open(os.path.join(folder, "report.json")))
        for run in report["runs"]:
            strategies = (run.get("image") or {}).get("files", {}).get("strategies")
            if not strategies:
                continue
            layers = read_layers(os.path.join(folder, strategies))
            runs.setdefault(run_label(run), (run["integrand"], []))[1].append(layers)
    pooled = {}
    for integrand, draws in runs.values():
        pooled.setdefault(integrand, []).extend(sum(d.values()) for d in draws)
    scale = {k: np.mean(v, 0) + 0.01 * np.mean(v) for k, v in pooled.items()}
    for label, (integrand, draws) in runs.items():
        if len(draws) < 2:
            print(f"{label}: in one folder only, no variance")
            continue
        s = scale[integrand]
        total_mean = np.mean([sum(d.values()) for d in draws], 0).sum()
        total = np.mean(np.var(np.stack([sum(d.values()) for d in draws]), 0, ddof=1) / s**2)
        print(f"{label}: relative variance of the run's mean {total:.4g} ({len(draws)} seeds)")
        rows = []
        for layer in draws[0]:
            stack = np.stack([d[layer] for d in draws])
            variance = np.mean(np.var(stack, 0, ddof=1) / s**2)
            share = stack.mean(0).sum() / total_mean if total_mean else 0.0
            rows.append((variance, layer, share))
        for variance, layer, share in sorted(rows, reverse=True)[:top]:
            print(f"  {layer:8s} variance {variance:9.4g} ({variance / total:6.1%} of the total)"
                  f"  mean {share:6.1%} of the image")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
