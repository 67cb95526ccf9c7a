"""pcbench plot REPORT.json [--out DIR]: the figures of a report and index.html beside them.

Run by `pcbench plot` with Debian's /usr/bin/python3 (matplotlib, OpenImageIO). Reads only the
report and the files it names. Exit status: 0 written, 2 bad input (no such report, not a
pcbench report, an output folder that is a file), 3 a figure could not be made.
"""

import argparse
import os
import re
import sys
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

EXIT_BAD_INPUT = 2
EXIT_FAILED = 3

try:
    import report_view  # noqa: E402  (found through the path set above)
    from convergence_figures import (convergence_figure, efficiency_ratio_figure,  # noqa: E402
                                     has_series)
    from figure_style import EstimatorColours  # noqa: E402
    from html_page import page  # noqa: E402
    from image_figures import image_set_figure, scene_figure  # noqa: E402
    from tile_calibration_figures import tile_calibration_figure  # noqa: E402
    from verification_figures import (calibration_qq_figure, has_tests,  # noqa: E402
                                      verification_figure)
except ImportError as missing:
    print(f"pcbench: error: plot: {missing} in {sys.executable} (Debian's python3-matplotlib: "
          "bash scripts/install-deps.sh)", file=sys.stderr)
    sys.exit(EXIT_FAILED)


def slug(text):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_")[:80] or "figure"


def make_sections(report, report_dir, out_dir):
    runs = report.get("runs") or []
    colours = EstimatorColours()
    sections = []
    tests = []
    if has_tests(report):
        tests.append((verification_figure(report, os.path.join(out_dir, "verification.png")),
                      "z-scores per run, p-values of honest runs against the uniform, power"))
    if report.get("calibration"):
        path = calibration_qq_figure(report["calibration"],
                                     os.path.join(out_dir, "calibration_qq.png"))
        if path:
            tests.append((path, "calibration p-values per estimator"))
    if report.get("tile_calibration"):
        tests.append((tile_calibration_figure(report["tile_calibration"],
                                              os.path.join(out_dir, "tile_calibration.png")),
                      "tile test calibration: detection rate against k × the MDB, with the "
                      "predicted power; false-alarm rates against α"))
    sections.append(("Verification", tests))

    analytic = [r for r in runs if not report_view.is_scene(r)]
    convergence = []
    for group, members in report_view.by_integrand(analytic).items():
        if not has_series(members) and not any(
                report_view.field(r, "aggregates", "efficiency") for r in members):
            continue
        path = os.path.join(out_dir, f"convergence_{slug(group)}.png")
        convergence.append((convergence_figure(group, members, colours, path),
                            f"{group}: RMSE against samples and CPU time, efficiency"))
    ratios = efficiency_ratio_figure(report.get("efficiency_ratios") or [],
                                     os.path.join(out_dir, "efficiency_ratios.png"))
    if ratios:
        convergence.insert(0, (ratios, "efficiency of each run relative to the first honest run "
                                       "on its integrand"))
    sections.append(("Convergence and efficiency", convergence))

    scenes = []
    for group, members in report_view.by_integrand(
            [r for r in runs if report_view.is_scene(r)]).items():
        path = scene_figure(group, members, report_dir,
                            os.path.join(out_dir, f"scene_{slug(group)}.png"))
        if path:
            scenes.append((path, f"{group}: reference, estimate, relative error, z-map"))
    image_set = image_set_figure(report, report_dir, os.path.join(out_dir, "image_set.png"))
    if image_set:
        scenes.append((image_set, "verify --images: the set's mean, its relative standard error "
                                  "and its z-map, the tiles that differ outlined"))
    sections.append(("Scenes", scenes))
    return sections


def write_atomically(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def main(argv):
    parser = argparse.ArgumentParser(prog="pcbench plot", description=__doc__.splitlines()[0])
    parser.add_argument("report", help="a report.json written by pcbench")
    parser.add_argument("--out", help="folder for the figures and index.html "
                        "(default: plots/ beside the report)")
    args = parser.parse_args(argv)
    try:
        report = report_view.load(args.report)
    except report_view.ReportError as e:
        print(f"pcbench: error: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    report_dir = os.path.dirname(os.path.abspath(args.report))
    out_dir = os.path.abspath(args.out) if args.out else os.path.join(report_dir, "plots")
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        print(f"pcbench: error: --out {out_dir}: exists and is not a folder", file=sys.stderr)
        return EXIT_BAD_INPUT
    os.makedirs(out_dir, exist_ok=True)
    try:
        sections = make_sections(report, report_dir, out_dir)
        index = os.path.join(out_dir, "index.html")
        write_atomically(index, page(report, os.path.abspath(args.report), report_dir, out_dir,
                                     sections))
    except Exception:  # a report the figures cannot handle is a bug to see, with its trace
        traceback.print_exc()
        print(f"pcbench: error: plotting {args.report} failed", file=sys.stderr)
        return EXIT_FAILED
    print(f"page: {index}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
