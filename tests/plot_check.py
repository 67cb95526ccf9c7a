"""`pcbench plot` on short reports of every kind: each figure is made, and the page renders.

    plot_check.py PCBENCH SOURCE_DIR

Reports: analytic runs with a negative control (series, efficiency and its ratios, tests), scenes (images with
exact and run references), `verify --images` on two exported replicate sets (image_sets), a calibration (power curve measured), a tile calibration (power and
false alarms of the scene tile test), and the analytic report with its optional sections (series,
images, comparisons, diagnostics) removed. For each: the figures
the report calls for exist as PNG files, index.html passes tests/page_check.py in headless
Chromium (no console error, every image decodes, the table matches the report), and bad input
exits 2 without writing.
"""

import copy
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_log import check, summary  # noqa: E402
from page_check import check_page  # noqa: E402

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def run(cmd, expect=0):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != expect:
        raise AssertionError(f"{' '.join(cmd)}: exit {done.returncode}, expected {expect}\n"
                             f"{done.stdout}\n{done.stderr}")
    return done


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == PNG_SIGNATURE and os.path.getsize(path) > 2000


def check_plotted(pcbench, report, expected_figures, name):
    out = os.path.join(os.path.dirname(report), "plots")
    done = run([pcbench, "plot", report])
    check(f"page: {os.path.join(out, 'index.html')}" in done.stdout,
          f"{name}: prints where the page is", done.stdout)
    made = sorted(f for f in os.listdir(out) if f.endswith(".png"))
    check(made == sorted(expected_figures), f"{name}: figures {expected_figures}", str(made))
    check(all(is_png(os.path.join(out, f)) for f in made), f"{name}: every figure is a PNG")
    failures, seen = check_page(os.path.join(out, "index.html"), report)
    check(not failures, f"{name}: the page renders without errors and its table matches the "
          f"report ({len(seen['rows'])} rows, {len(seen['images'])} images)", "; ".join(failures))
    check(len(seen["images"]) == len(made), f"{name}: every figure is on the page")


def main():
    pcbench = sys.argv[1]  # argv[2], the source folder, is not needed
    with tempfile.TemporaryDirectory() as scratch:
        analytic = os.path.join(scratch, "analytic")
        # Exit 0: the control is expected biased and flagged.
        run([pcbench, "verify", "-e", "plain,pcbpt,ctl-wrong-count", "-i",
             "form-factor,genz-gaussian", "-n", "8192", "-r", "8", "--out", analytic, "-q"])
        check_plotted(pcbench, os.path.join(analytic, "report.json"),
                      ["verification.png", "convergence_form-factor.png",
                       "convergence_genz-gaussian.png", "efficiency_ratios.png"], "analytic")

        scenes = os.path.join(scratch, "scenes")
        run([pcbench, "run", "-e", "plain,pt", "-i", "furnace,cornell", "-p", "resolution=16",
             "-n", "4", "-r", "4", "--out", scenes, "-q"])
        check_plotted(pcbench, os.path.join(scenes, "report.json"),
                      ["verification.png", "scene_furnace.png", "scene_cornell.png"], "scenes")
        with open(os.path.join(scenes, "report.json")) as f:
            scene_runs = json.load(f)["runs"]
        check(all(os.path.isfile(os.path.join(scenes, r["image"]["files"]["reference"]))
                  for r in scene_runs), "scenes: every run names its reference image")

        # verify --images: two pcbench exports of the furnace (seeds 1 and 2) against each other.
        sets = []
        for seed in ("1", "2"):
            folder = os.path.join(scratch, "export" + seed)
            run([pcbench, "run", "-e", "pt", "-i", "furnace", "-p", "resolution=16", "-n", "4",
                 "-r", "4", "-s", seed, "--replicate-images", "--out", folder, "-q"])
            sets.append(",".join(sorted(
                os.path.join(folder, "images", f) for f in os.listdir(os.path.join(folder, "images"))
                if "_rep" in f)))
        images = os.path.join(scratch, "images")
        run([pcbench, "verify", "--images", sets[0], "--against", sets[1], "--out", images, "-q"])
        check_plotted(pcbench, os.path.join(images, "report.json"), ["image_set.png"],
                      "verify --images")

        calibration = os.path.join(scratch, "calibration")
        run([pcbench, "calibrate", "--seeds", "20", "-n", "500", "--out", calibration, "-q"])
        check_plotted(pcbench, os.path.join(calibration, "report.json"),
                      ["verification.png", "calibration_qq.png"], "calibration")

        tiles = os.path.join(scratch, "tile-calibration")
        run([pcbench, "calibrate", "-i", "furnace,cornell", "-p", "resolution=16", "--seeds", "20",
             "-n", "1", "-r", "4", "--out", tiles, "-q"])
        check_plotted(pcbench, os.path.join(tiles, "report.json"), ["tile_calibration.png"],
                      "tile calibration")

        # The same analytic report without any optional section still plots.
        bare = os.path.join(scratch, "bare")
        os.makedirs(bare)
        with open(os.path.join(analytic, "report.json")) as f:
            report = json.load(f)
        stripped = copy.deepcopy(report)
        stripped.pop("comparisons", None)
        stripped.pop("efficiency_ratios", None)
        for r in stripped["runs"]:
            for key in ("series", "image", "diagnostics", "escalation", "counters", "budget"):
                r.pop(key, None)
            r["aggregates"] = {k: None for k in r.get("aggregates") or {}}
        with open(os.path.join(bare, "report.json"), "w") as f:
            json.dump(stripped, f)
        check_plotted(pcbench, os.path.join(bare, "report.json"), ["verification.png"],
                      "without optional sections")

        # Bad input: exit 2 and no folder made.
        not_report = os.path.join(scratch, "not_report.json")
        with open(not_report, "w") as f:
            f.write('{"runs": ')
        for args in ([os.path.join(scratch, "missing.json")], [not_report],
                     [os.path.join(analytic, "report.json"), "--out", not_report]):
            done = subprocess.run([pcbench, "plot"] + args, capture_output=True, text=True)
            check(done.returncode == 2 and "error" in done.stderr,
                  f"bad input {args[-1]} exits 2 with a message", done.stderr)
        check(not os.path.exists(os.path.join(scratch, "plots")), "bad input writes nothing")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
