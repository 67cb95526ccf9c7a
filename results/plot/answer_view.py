"""What a report found, as the page opens with it: the verdict matrix and the tile maps.

The matrix has a row per estimator (with the parameters that tell its runs apart) and a column
per integrand or scene (report_view.by_integrand); a cell is the run's verdict and its equal-time
efficiency relative to the column's first honest run (the first run not expected biased that has
an efficiency): aggregates.efficiency for analytic runs, image.efficiency = 1 / (relative MSE at
one CPU second) for scene runs. tests/page_check.py recomputes both from the report.

The tile maps are drawn for image reports (scene runs, `verify --images`): per integrand, the
tile grid of its tile comparisons (not the "+injected" self-checks), each tile marked by the
comparisons that list it in tiles_differing (harness/report_compare.h), split into those expected
consistent (a difference nobody expected) and those expected biased (a control caught there).
"""

import report_view
from report_view import expectation_of, field, number, result_of


def efficiency(run):
    value = field(run, "image", "efficiency") if report_view.is_scene(run) else field(
        run, "aggregates", "efficiency")
    value = number(value)
    return value if value is not None and value > 0 else None


def estimator_labels(runs):
    """report_view.labels on the estimator's own parameters: a run's params also hold its
    integrand's (integrand_params), which the columns already tell apart."""
    own = []
    for run in runs:
        integrand = report_view.integrand_params(run)
        own.append(dict(run, params={k: v for k, v in (run.get("params") or {}).items()
                                     if k not in integrand}))
    return report_view.labels(own)


def verdict_matrix(report):
    """(row labels, column names, {(row, column): [cell]}); a cell is a dict with the run's id,
    result, expect and relative efficiency (None where either efficiency is missing)."""
    runs = report.get("runs") or []
    label_of = dict(zip((r["id"] for r in runs), estimator_labels(runs)))
    rows, columns, cells = [], [], {}
    for column, members in report_view.by_integrand(runs).items():
        columns.append(column)
        baseline = next((efficiency(r) for r in members
                         if expectation_of(r) != "biased" and efficiency(r) is not None), None)
        for run in members:
            row = label_of[run["id"]]
            if row not in rows:
                rows.append(row)
            mine = efficiency(run)
            cells.setdefault((row, column), []).append({
                "id": run["id"], "result": result_of(run), "expect": expectation_of(run),
                "status": run.get("status"),
                "relative": mine / baseline if mine is not None and baseline else None})
    return rows, columns, cells


def tiles_marked(c):
    """The tiles of a block comparison's map: those that differ at the finest scale, and every tile
    inside a block that differs at the coarsest scale where some block does (a bias spread over a
    region is often seen only there). {(x, y)} in tile coordinates."""
    marked = {(x, y) for x, y, _ in c.get("tiles_differing") or []}
    scales = c.get("scales") or []
    coarsest = c.get("coarsest_differing_block")
    if not scales or coarsest is None:
        return marked
    tile = scales[0]["block"]
    for scale in scales:
        if scale["block"] != coarsest:
            continue
        per = scale["block"] // tile
        for bx, by, _ in scale.get("blocks_differing") or []:
            for x in range(bx * per, min((bx + 1) * per, c["tile_columns"])):
                for y in range(by * per, min((by + 1) * per, c["tile_rows"])):
                    marked.add((x, y))
    return marked


def tile_maps(report):
    """{integrand: {"columns", "rows", "unexpected": {(x, y): [labels]}, "expected": {...},
    "comparisons": n}} for every integrand with tile comparisons."""
    maps = {}
    for c in report.get("comparisons") or []:
        if c.get("tile_columns") is None or str(c.get("a", "")).endswith("+injected"):
            continue
        entry = maps.setdefault(c.get("integrand", ""), {
            "columns": c["tile_columns"], "rows": c["tile_rows"], "unexpected": {},
            "expected": {}, "comparisons": 0})
        entry["comparisons"] += 1
        kind = "expected" if c.get("expect") == "biased" else "unexpected"
        for x, y in sorted(tiles_marked(c)):
            names = entry[kind].setdefault((x, y), [])
            if c.get("estimator") not in names:
                names.append(c.get("estimator"))
    return maps
