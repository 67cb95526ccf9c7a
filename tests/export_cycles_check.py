#!/usr/bin/python3
"""Blender's Cycles against pcbench, end to end: export, render replicates, verify (issue 38).

Usage:
    /usr/bin/python3 tests/export_cycles_check.py PATH/TO/pcbench SOURCE_DIR [--keep DIR]

With Debian's blender (3.4, Cycles on the CPU; scripts/install-deps.sh installs it with the test
packages), in a scratch folder holding build/release/pcbench:
  1. docs/guide/your-renderer.md's first ```console block, as written: export cornell at 64x64,
     render 8 Cycles replicates of 64 spp with blender -b, pcbench's own `pt` replicates, and
     `verify --images` Cycles against them: each exits 0, the exported README gives the same
     lines, Cycles is consistent at every scale, and the whole image's detectable bias is printed
     (and below 1%, so that step 3 means something); render.py into the filled folder again is
     refused (exit 2), the set left as it was;
  2. the furnace exported at 64x64 and its README's commands run as written: Cycles' replicates
     consistent with the exact image (`--constant`);
  3. Cycles' cornell set made 1% darker (OpenImageIO and numpy): flagged (`--expect biased`
     exits 0), and the whole image's scale is among those that differ;
  4. cornell-glossy is refused (exit 2, naming its Phong material and Cycles), nothing written;
     with --approximate it is written and its README expects biased.
Each verify is one family at alpha = 0.01 with fixed seeds (Cycles' 1..8, pcbench's 1): the
consistent steps pass with probability >= 99% when Cycles and pcbench render the same image, the
biased one where the detectable bias printed in step 1 is below 1%. Prints one line per check,
the wall time of each command and in all, and "N passed, M failed"; exits 1 if any check failed.
"""

import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenImageIO as oiio

from check_log import check, summary

REPLICATES = 8
GUIDE = "docs/guide/your-renderer.md"


def run(line, cwd, what=None):
    """Runs a command line with bash in `cwd`; the finished process, its wall time printed."""
    start = time.monotonic()
    done = subprocess.run(["bash", "-c", line], cwd=cwd, capture_output=True, text=True)
    print(f"        {time.monotonic() - start:6.1f} s  exit {done.returncode}  {what or line}",
          flush=True)
    return done


def report(folder):
    with open(os.path.join(folder, "report.json")) as f:
        return json.load(f)


def whole_image_line(comparison):
    scales = comparison["scales"]
    image = scales[-1]
    return (f"whole image ({image['block']} px): detectable bias {100 * image['relative_mdb']:.3g}%"
            f" (required {100 * image['required_mdb']:.3g}%); per scale (worst, median): "
            + ", ".join(f"{s['block']} px {100 * s['relative_mdb']:.3g}% "
                        f"{100 * s['median_relative_mdb']:.3g}%" for s in scales))


def block(text, fence, after):
    """The lines of the first ```fence block after the line `after`."""
    lines = text[text.index(after):].splitlines()
    start = lines.index("```" + fence) + 1
    return [line for line in lines[start:lines.index("```", start)] if line.strip()]


def readme_lines(folder):
    with open(os.path.join(folder, "README.md")) as f:
        return block(f.read(), "sh", "## Render, then verify")


def as_written(lines, scratch):
    """Runs each line in the scratch folder, pcbench as build/release/pcbench; all exit 0?"""
    ok = True
    for line in lines:
        line = "build/release/" + line if line.startswith("pcbench ") else line
        done = run(line, scratch)
        ok = check(done.returncode == 0, f"exits 0: {line[:70]}",
                   (done.stdout + done.stderr)[-3000:]) and ok
    return ok


def darker_copy(files, out):
    """Every replicate times 0.99, as 32-bit float EXR."""
    os.makedirs(out)
    for path in files:
        image = oiio.ImageBuf(path)
        pixels = image.get_pixels(oiio.FLOAT)
        spec = oiio.ImageSpec(image.spec().width, image.spec().height, pixels.shape[2],
                              oiio.FLOAT)
        spec.channelnames = image.spec().channelnames
        target = oiio.ImageOutput.create(os.path.join(out, os.path.basename(path)))
        target.open(os.path.join(out, os.path.basename(path)), spec)
        target.write_image(np.ascontiguousarray(pixels * np.float32(0.99)))
        target.close()


def cornell(source, scratch):
    with open(os.path.join(source, GUIDE)) as f:
        guide = block(f.read(), "console", "## Three commands")
    check(len(guide) == 4 and guide[0].startswith("build/release/pcbench export cornell"),
          "the guide opens with export, render and verify", "\n".join(guide))
    start = time.monotonic()
    if not as_written(guide, scratch):
        return
    print(f"        the guide's commands: {time.monotonic() - start:.1f} s", flush=True)
    folder = os.path.join(scratch, "results", "cycles-cornell")
    written = ["build/release/" + line if line.startswith("pcbench ") else line
               for line in readme_lines(folder)]
    check(written == guide[1:], "the exported README gives the guide's render and verify lines",
          "\n".join(written))
    cycles_set = os.path.join(folder, "cycles", "*.exr")
    check(len(glob.glob(cycles_set)) == REPLICATES, f"{REPLICATES} Cycles replicates (EXR)")
    again = run(guide[1].replace("--replicates 8", "--replicates 2"), scratch,
                "render.py into the filled folder again")
    check(again.returncode == 2 and "not an empty folder" in again.stderr
          and len(glob.glob(cycles_set)) == REPLICATES,
          "render.py refuses a folder that holds an earlier render (exit 2)", again.stderr[-500:])
    comparison = report(os.path.join(folder, "verify"))["comparisons"][0]
    check(comparison["result"] == "consistent", "cornell: Cycles consistent with pcbench's pt at "
          "every scale", comparison["reason"])
    print("        cornell, Cycles against pt: " + whole_image_line(comparison), flush=True)
    image_mdb = comparison["scales"][-1]["relative_mdb"]
    check(image_mdb < 0.01, "cornell: the whole image detects a bias below 1%",
          f"{100 * image_mdb:.3g}%")
    check(comparison["replicates_b"] == REPLICATES and comparison["mean_b"] > 0,
          "cornell: the report's whole-image figures are both sets'", str(comparison)[:500])

    darker = os.path.join(scratch, "cornell-darker")
    darker_copy(sorted(glob.glob(cycles_set)), darker)
    pcbench_set = os.path.join(folder, "pcbench", "images", "*_rep*.exr")
    out = os.path.join(scratch, "verify-darker")
    done = run(f"build/release/pcbench verify --images {darker} --against '{pcbench_set}' "
               f"--expect biased -q --out {out}", scratch, "verify the 1% darker set")
    check(done.returncode == 0, "cornell 1% darker: flagged (--expect biased exits 0)",
          done.stdout + done.stderr)
    flagged = report(out)["comparisons"][0]
    check(len(flagged["scales"][-1]["blocks_differing"]) > 0,
          "cornell 1% darker: the whole image's scale differs",
          f"coarsest differing block {flagged['coarsest_differing_block']}")


def furnace(scratch):
    folder = "results/cycles-furnace"
    done = run(f"build/release/pcbench export furnace --to cycles -p resolution=64 --out {folder}",
               scratch)
    check(done.returncode == 0, "export furnace exits 0", done.stderr)
    lines = readme_lines(os.path.join(scratch, folder))
    check(len(lines) == 2 and "--constant" in lines[1],
          "the furnace's README renders and verifies against its exact image", "\n".join(lines))
    if as_written(lines, scratch):
        comparison = report(os.path.join(scratch, folder, "verify"))["comparisons"][0]
        check(comparison["result"] == "consistent", "furnace: Cycles consistent with its exact "
              "image", comparison["reason"])
        print("        furnace, Cycles against exact: " + whole_image_line(comparison), flush=True)


def refusals(scratch):
    glossy = os.path.join(scratch, "glossy")
    done = run(f"build/release/pcbench export cornell-glossy --to cycles --out {glossy}", scratch)
    check(done.returncode == 2 and "(phong, exponent" in done.stderr and "Cycles" in done.stderr,
          "cornell-glossy is refused (exit 2), naming its Phong material and Cycles", done.stderr)
    check(not os.path.exists(glossy), "nothing written for a refused export")
    done = run(f"build/release/pcbench export cornell-glossy --to cycles --approximate "
               f"--out {glossy}", scratch)
    check(done.returncode == 0, "--approximate writes it", done.stderr)
    lines = readme_lines(glossy) if done.returncode == 0 else []
    check(any("--expect biased" in line for line in lines),
          "its README verifies with --expect biased", "\n".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pcbench")
    parser.add_argument("source")
    parser.add_argument("--keep", help="work in this (new) folder and keep it")
    args = parser.parse_args()
    if shutil.which("blender") is None:
        print("FAILED  blender not found: `bash scripts/install-deps.sh` installs Debian's")
        return 1
    start = time.monotonic()
    scratch = args.keep or tempfile.mkdtemp(prefix="pcbench-cycles-")
    os.makedirs(os.path.join(scratch, "build", "release"), exist_ok=True)
    os.symlink(os.path.abspath(args.pcbench), os.path.join(scratch, "build", "release", "pcbench"))
    try:
        cornell(args.source, scratch)
        furnace(scratch)
        refusals(scratch)
    finally:
        if not args.keep:
            shutil.rmtree(scratch, ignore_errors=True)
    print(f"        wall time: {time.monotonic() - start:.1f} s in all")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
