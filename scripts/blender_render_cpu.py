#!/usr/bin/python3
"""Usage: scripts/blender_render_cpu.py EXPORT_DIR OUT --spp N --first-seed S [--replicates R]
          [--threads T] [--blender BLENDER]

Renders R replicates (default 2, the least render.py takes) of a scene written by `pcbench export
SCENE --to cycles --out EXPORT_DIR` with Cycles at N spp, seeds S .. S+R-1, then the same
replicates at 1 spp, each as one `blender -b -P EXPORT_DIR/render.py -- ...` process, and
measures each process's CPU seconds (the children's rusage user + sys around it). Images go to
OUT/spp<N>/seed<S>/cycles_rep<k>.exr and OUT/spp1/seed<S>/; every process appends one JSON line
to OUT/cpu.jsonl (spp, seeds, files, user, sys, wall, and Blender's own `Time:` per render, which
is wall time). Then OUT/cpu-<N>.csv and OUT/cpu-1.csv are rewritten from the whole log, one
row per replicate, `file,spp,gross_cpu_seconds,cpu_seconds` (gross: the process's CPU / R; at
1 spp cpu_seconds is nan), where cpu_seconds is what the replicate's N samples cost:
(the process's CPU − the mean CPU of the 1-spp processes) / R × N / (N − 1). The 1-spp process
does everything the N-spp one does (start Blender, build the scene, sync it and build the BVH for
each replicate, write the EXRs) but 1 sample per pixel, so the difference is the cost of N − 1
samples; averaging the 1-spp processes over the whole log keeps their noise small. Run it once
per block of replicates, interleaved with the renderers it is compared with.
"""
import argparse
import json
import math
import os
import re
import resource
import subprocess
import sys
import time


def render(args, spp):
    """One blender process: R replicates at spp; returns its log record."""
    folder = os.path.join(args.out, f"spp{spp}", f"seed{args.first_seed}")
    command = [args.blender, "-b", "-P", os.path.join(args.export_dir, "render.py"), "--",
               "--replicates", str(args.replicates), "--spp", str(spp), "--out", folder,
               "--threads", str(args.threads), "--first-seed", str(args.first_seed)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"{' '.join(command)} exited {done.returncode}:\n{done.stdout[-3000:]}")
    # Blender's summary per render: " Time: 00:03.21 (Saving: 00:00.00)" (wall time).
    times = [60 * float(m) + float(s)
             for m, s in re.findall(r"^\s*Time: (\d+):(\d+\.\d+) \(Saving", done.stdout, re.M)]
    files = [os.path.join(folder, f"cycles_rep{k:03d}.exr") for k in range(args.replicates)]
    return {"spp": spp, "first_seed": args.first_seed, "replicates": args.replicates,
            "threads": args.threads, "files": files,
            "user": after.ru_utime - before.ru_utime, "sys": after.ru_stime - before.ru_stime,
            "wall": wall, "blender_times": times, "date": time.strftime("%Y-%m-%dT%H:%M:%S")}


def write_tables(out):
    records = [json.loads(line) for line in open(os.path.join(out, "cpu.jsonl"))]
    base = [r["user"] + r["sys"] for r in records if r["spp"] == 1]
    base = sum(base) / len(base)
    for spp in sorted({r["spp"] for r in records}):
        with open(os.path.join(out, f"cpu-{spp}.csv"), "w") as table:
            table.write("file,spp,gross_cpu_seconds,cpu_seconds\n")
            for r in (r for r in records if r["spp"] == spp):
                gross = r["user"] + r["sys"]
                net = (gross - base) / r["replicates"] * spp / (spp - 1) if spp > 1 else math.nan
                for f in r["files"]:
                    table.write(f"{f},{spp},{gross / r['replicates']:.6f},{net:.6f}\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("export_dir")
    parser.add_argument("out")
    parser.add_argument("--spp", type=int, required=True)
    parser.add_argument("--first-seed", type=int, required=True)
    parser.add_argument("--replicates", type=int, default=2)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--blender", default="blender")
    args = parser.parse_args()
    if args.spp < 2:
        parser.error("--spp >= 2 (the 1-spp render is the start-up baseline)")
    os.makedirs(args.out, exist_ok=True)
    for spp in (args.spp, 1):
        record = render(args, spp)
        with open(os.path.join(args.out, "cpu.jsonl"), "a") as log:
            log.write(json.dumps(record) + "\n")
        print(f"cycles {spp} spp, seeds {args.first_seed}+{args.replicates}: "
              f"{record['user'] + record['sys']:.2f} CPU s, {record['wall']:.2f} s wall, "
              f"Blender's times {record['blender_times']}", flush=True)
    write_tables(args.out)


if __name__ == "__main__":
    main()
