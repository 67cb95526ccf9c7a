"""index.html: the answer first (the verdict matrix, the maps of tiles that differ), then the
context, the table of runs with coloured verdicts, comparisons, the figures.

Self-contained: the figures are embedded as data URIs and the style sheet is inline, so the page
needs no network and can be mailed alone; only the links to the EXR files point beside it. Every
row carries its run id and verdict as data attributes (tests/plot_check.py compares them with
the report).
"""

import base64
import html
import os

from answer_view import tile_maps, verdict_matrix
from report_view import (VERDICT_COLOURS, expectation_of, field, number, relative_link,
                         result_of)

_STYLE = """
body { font-family: sans-serif; margin: 1.5em; color: #212121; }
h1 { font-size: 1.4em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
table { border-collapse: collapse; font-size: 0.8em; }
th, td { border: 1px solid #ddd; padding: 2px 6px; text-align: left; vertical-align: top; }
th { background: #f5f5f5; position: sticky; top: 0; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.verdict { color: white; font-weight: bold; }
td.reason { min-width: 28em; }
tr.unexpected td { background: #fff3e0; }
dl.context { display: grid; grid-template-columns: max-content auto; gap: 0 1em;
             font-size: 0.85em; }
dl.context dt { font-weight: bold; }
figure { margin: 1em 0; } figure img { max-width: 100%; }
figcaption { font-size: 0.8em; color: #555; }
.summary span { display: inline-block; margin-right: 1em; }
table.matrix td.cell { color: white; text-align: center; min-width: 4.5em; font-weight: bold; }
table.matrix td.cell.unexpected { outline: 3px solid #000; outline-offset: -3px; }
table.matrix td.empty { background: #fafafa; }
table.matrix th.row { text-align: right; position: static; white-space: nowrap; }
.legend span { display: inline-block; margin-right: 1em; font-size: 0.8em; }
.legend i { display: inline-block; width: 0.9em; height: 0.9em; margin-right: 0.3em;
            vertical-align: middle; }
.tilemaps { display: flex; flex-wrap: wrap; gap: 1.5em; }
.tilemap { font-size: 0.8em; }
.tilegrid { display: grid; gap: 1px; background: #bbb; border: 1px solid #bbb; }
.tilegrid div { aspect-ratio: 1; background: #e8f5e9; font-size: 0.7em; color: white;
                text-align: center; overflow: hidden; }
.tilegrid div.unexpected { background: #c62828; }
.tilegrid div.expected { background: #8d6e63; }
"""


def _fmt(value, digits=4):
    value = number(value)
    if value is None:
        return "—"
    return f"{value:.{digits}g}"


def _percent(value):
    value = number(value)
    return "—" if value is None else f"{100 * value:.2g}%"


def _cell(text, cls=None, **data):
    attrs = "".join(f' data-{k}="{html.escape(str(v))}"' for k, v in data.items())
    cls_attr = f' class="{cls}"' if cls else ""
    return f"<td{cls_attr}{attrs}>{html.escape(str(text))}</td>"


def _verdict_cell(result):
    colour = VERDICT_COLOURS.get(result, VERDICT_COLOURS[None])
    return (f'<td class="verdict" style="background:{colour}" data-verdict="{result or ""}">'
            f"{html.escape(result or 'not tested')}</td>")


def _params_text(run):
    return " ".join(f"{k}={v}" for k, v in (run.get("params") or {}).items())


def _estimate_text(run):
    image = run.get("image")
    if isinstance(image, dict):
        return f"image {image.get('width')}×{image.get('height')}"
    mean, se = field(run, "aggregates", "mean"), field(run, "aggregates", "stderr")
    return f"{_fmt(mean, 6)} ± {_fmt(se, 2)}"


def _efficiency_text(run):
    image = run.get("image")
    if isinstance(image, dict):
        return f"{_fmt(image.get('efficiency'), 3)} (1/(relMSE·s))"
    eff = field(run, "aggregates", "efficiency")
    low, high = field(run, "aggregates", "efficiency_low"), field(run, "aggregates",
                                                                  "efficiency_high")
    return f"{_fmt(eff, 3)} [{_fmt(low, 2)}, {_fmt(high, 2)}]"


def _rel_mse(run):
    image = run.get("image")
    if isinstance(image, dict):
        return image.get("rel_mse")
    return field(run, "aggregates", "rel_mse")


def runs_table(runs, report_dir, out_dir):
    head = ("id", "estimator", "integrand", "params", "samples × replicates", "status",
            "estimate ± stderr", "reference", "bias", "rel MSE", "efficiency [95%]", "mdb/|f|",
            "verdict", "expected", "images")
    rows = ["<table id='runs'><thead><tr>" + "".join(f"<th>{h}</th>" for h in head) +
            "</tr></thead><tbody>"]
    for run in runs:
        result, expect = result_of(run), expectation_of(run)
        unexpected = result is not None and expect is not None and result != expect
        reps = len(run.get("replicates") or [])
        ref = run.get("reference") or {}
        files = field(run, "image", "files") or {}
        links = " ".join(
            f'<a href="{html.escape(relative_link(report_dir, out_dir, name))}">{kind}</a>'
            for kind, name in files.items() if name)
        cells = [
            _cell(run["id"], "id"),
            _cell(run["estimator"]),
            _cell(run["integrand"]),
            _cell(_params_text(run)),
            _cell(f"{run.get('samples')} × {reps}", "num"),
            _cell(run.get("status"), "status", status=run.get("status")),
            _cell(_estimate_text(run), "num"),
            _cell(f"{_fmt(ref.get('value'), 6)} ({ref.get('kind', 'none')})", "num"),
            _cell(_fmt(field(run, "aggregates", "bias"), 3), "num"),
            _cell(_fmt(_rel_mse(run), 3), "num"),
            _cell(_efficiency_text(run), "num"),
            _cell(_percent(field(run, "verdict", "min_detectable_bias_vs_mean_abs")), "num"),
            _verdict_cell(result),
            _cell(expect or "—", "expect"),
            f"<td>{links}</td>",
        ]
        cls = ' class="unexpected"' if unexpected else ""
        rows.append(f'<tr data-run-id="{html.escape(run["id"])}"{cls}>' + "".join(cells) +
                    "</tr>")
        if run.get("error"):
            rows.append(f"<tr><td></td><td colspan='{len(head) - 1}'>"
                        f"{html.escape(str(run['error']))}</td></tr>")
    rows.append("</tbody></table>")
    return "\n".join(rows)


def comparisons_table(comparisons):
    if not comparisons:
        return ""
    head = ("a", "b", "estimators", "integrand", "test", "p", "p adjusted", "result", "expected",
            "reason")
    rows = ["<h2>Comparisons</h2><table id='comparisons'><thead><tr>" +
            "".join(f"<th>{h}</th>" for h in head) + "</tr></thead><tbody>"]
    for c in comparisons:
        rows.append("<tr>" + "".join([
            _cell(c.get("a")), _cell(c.get("b")), _cell(c.get("estimator", "")),
            _cell(c.get("integrand", "")), _cell(c.get("test")),
            _cell(_fmt(c.get("p_value"), 3), "num"), _cell(_fmt(c.get("p_adjusted"), 3), "num"),
            _verdict_cell(c.get("result")), _cell(c.get("expect")),
            _cell(c.get("reason", ""), "reason")
        ]) + "</tr>")
    rows.append("</tbody></table>")
    return "\n".join(rows)


def ratios_table(ratios):
    if not ratios:
        return ""
    head = ("estimators", "integrand", "efficiency ratio", "interval", "variance ratio",
            "cost ratio", "pairs", "interleaved")
    rows = ["<h2>Efficiency ratios</h2><table id='efficiency-ratios'><thead><tr>" +
            "".join(f"<th>{h}</th>" for h in head) + "</tr></thead><tbody>"]
    for r in ratios:
        level = number(r.get("level")) or 0.95
        rows.append("<tr>" + "".join([
            _cell(r.get("estimator")), _cell(r.get("integrand")),
            _cell(_fmt(r.get("ratio"), 3), "num"),
            _cell(f"[{_fmt(r.get('low'), 3)}, {_fmt(r.get('high'), 3)}] "
                  f"({100 * level:.0f}%)", "num"),
            _cell(_fmt(r.get("variance_ratio"), 3), "num"),
            _cell(_fmt(r.get("cost_ratio"), 3), "num"), _cell(r.get("pairs"), "num"),
            _cell("yes" if r.get("interleaved") else "no")
        ]) + "</tr>")
    rows.append("</tbody></table>")
    return "\n".join(rows)


def context_block(report, report_path):
    ctx = report.get("context") or {}
    keys = ("date", "host", "cpu", "cores", "compiler", "flags", "build_type", "git_commit",
            "git_dirty", "seed", "threads", "pcbench_version")
    items = [("report", report_path), ("suite", report.get("suite", ""))]
    items += [(k, ctx[k]) for k in keys if k in ctx]
    if ctx.get("argv"):
        items.append(("command", " ".join(ctx["argv"])))
    return "<dl class='context'>" + "".join(
        f"<dt>{html.escape(str(k))}</dt><dd>{html.escape(str(v))}</dd>" for k, v in items
    ) + "</dl>"


def summary_line(runs, comparisons):
    counts = {}
    for run in runs:
        key = result_of(run) or run.get("status", "?")
        counts[key] = counts.get(key, 0) + 1
    unexpected = sum(1 for r in runs if result_of(r) and result_of(r) != expectation_of(r))
    unexpected += sum(1 for c in comparisons if c.get("result") != c.get("expect"))
    parts = [f"<span>{len(runs)} runs</span>"]
    parts += [f"<span style='color:{VERDICT_COLOURS.get(k, VERDICT_COLOURS[None])}'>"
              f"{html.escape(str(k))}: {n}</span>" for k, n in sorted(counts.items())]
    parts.append(f"<span id='unexpected' data-count='{unexpected}'>"
                 f"differ from their expectation: {unexpected}</span>")
    return "<p class='summary'>" + "".join(parts) + "</p>"


def _relative_text(value):
    value = number(value)
    if value is None:
        return "—"
    return f"{value:.2g}×" if value < 10 else f"{value:.0f}×"


def matrix_block(report):
    """The verdict matrix: estimator × integrand, coloured by verdict, with each run's
    equal-time efficiency relative to its column's first honest run (answer_view.py)."""
    rows, columns, cells = verdict_matrix(report)
    if not rows:
        return ""
    out = ["<h2 id='answer'>What this report found</h2>",
           "<p class='legend'>" + "".join(
               f"<span><i style='background:{VERDICT_COLOURS.get(k, VERDICT_COLOURS[None])}'>"
               f"</i>{k or 'not tested'}</span>"
               for k in ("consistent", "biased", "inconclusive", None)) +
           "<span>framed: the verdict differs from its expectation</span>"
           "<span>number: equal-time efficiency relative to the first honest run in the column"
           "</span></p>",
           "<table id='matrix' class='matrix'><thead><tr><th></th>" +
           "".join(f"<th>{html.escape(c)}</th>" for c in columns) + "</tr></thead><tbody>"]
    for row in rows:
        line = [f"<tr><th class='row'>{html.escape(row)}</th>"]
        for column in columns:
            found = cells.get((row, column))
            if not found:
                line.append("<td class='empty'></td>")
                continue
            for cell in found:
                result, expect = cell["result"], cell["expect"]
                colour = VERDICT_COLOURS.get(result, VERDICT_COLOURS[None])
                unexpected = result is not None and expect is not None and result != expect
                title = (f"{cell['id']}: {result or cell['status']}"
                         f" (expected {expect or '—'})")
                line.append(
                    f"<td class='cell{' unexpected' if unexpected else ''}' "
                    f"style='background:{colour}' data-run-id='{html.escape(cell['id'])}' "
                    f"data-verdict='{result or ''}' data-relative='{cell['relative'] or ''}' "
                    f"title='{html.escape(title)}'>{_relative_text(cell['relative'])}</td>")
        out.append("".join(line) + "</tr>")
    out.append("</tbody></table>")
    return "\n".join(out)


def tile_maps_block(report):
    """Per integrand with tile comparisons: its tile grid, each tile marked by the comparisons
    that found it different (red: expected consistent; brown: a control caught, as expected)."""
    maps = tile_maps(report)
    if not maps:
        return ""
    out = ["<p class='legend'><span>Tiles that differ, over the image (row 0 at the top; "
           "the number: how many comparisons found the tile different):</span>"
           "<span><i style='background:#c62828'></i>in a comparison expected consistent</span>"
           "<span><i style='background:#8d6e63'></i>only where a control was expected to differ"
           "</span><span><i style='background:#e8f5e9'></i>no difference found</span></p>",
           "<div class='tilemaps'>"]
    for integrand, m in maps.items():
        grid = [f"<div class='tilemap' data-integrand='{html.escape(integrand)}'>"
                f"<b>{html.escape(integrand)}</b> ({m['comparisons']} comparisons, "
                f"{m['columns']}×{m['rows']} tiles)",
                f"<div class='tilegrid' style='grid-template-columns:repeat({m['columns']},1fr);"
                f"width:{min(16, 2 * m['columns'])}em'>"]
        for y in range(m["rows"]):
            for x in range(m["columns"]):
                unexpected = m["unexpected"].get((x, y), [])
                expected = m["expected"].get((x, y), [])
                names = unexpected or expected
                kind = "unexpected" if unexpected else "expected" if expected else ""
                title = f"tile {x},{y}" + (": " + "; ".join(names) if names else "")
                grid.append(f"<div class='{kind}' data-tile='{x},{y}' "
                            f"data-flags='{len(names)}' title='{html.escape(title)}'>"
                            f"{len(names) if names else ''}</div>")
        grid.append("</div></div>")
        out.append("".join(grid))
    out.append("</div>")
    return "\n".join(out)


def figure(path, caption):
    with open(path, "rb") as f:
        data = base64.b64encode(f.read()).decode("ascii")
    name = os.path.basename(path)
    return (f"<figure data-file='{html.escape(name)}'><img alt='{html.escape(caption)}' "
            f"src='data:image/png;base64,{data}'><figcaption>{html.escape(caption)} "
            f"(<a href='{html.escape(name)}'>{html.escape(name)}</a>)</figcaption></figure>")


def _anchor(heading):
    return "".join(c if c.isalnum() else "-" for c in heading.lower())


def page(report, report_path, report_dir, out_dir, sections):
    """The whole page; `sections` is a list of (heading, [(png path, caption)])."""
    runs = report.get("runs") or []
    comparisons = report.get("comparisons") or []
    title = f"pcbench: {report.get('suite', 'report')}"
    answer = matrix_block(report)
    maps = tile_maps_block(report)
    if maps and not answer:
        answer = "<h2 id='answer'>What this report found</h2>"
    body = [f"<h1>{html.escape(title)}</h1>", summary_line(runs, comparisons), answer + maps,
            "<h2 id='context'>Context</h2>", context_block(report, report_path),
            "<h2 id='runs-heading'>Runs</h2>",
            runs_table(runs, report_dir, out_dir) if runs else "<p>No runs in this report.</p>",
            comparisons_table(comparisons), ratios_table(report.get("efficiency_ratios"))]
    contents = [("answer", "What this report found")] if answer else []
    contents += [("context", "Context"), ("runs-heading", "Runs")]
    contents += [(_anchor(h), h) for h, figures in sections if figures]
    body.insert(1, "<p class='contents'>" + " · ".join(
        f"<a href='#{a}'>{html.escape(h)}</a>" for a, h in contents) + "</p>")
    for heading, figures in sections:
        if figures:
            body.append(f"<h2 id='{_anchor(heading)}'>{html.escape(heading)}</h2>")
            body += [figure(path, caption) for path, caption in figures]
    return ("<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
            f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>\n" +
            "\n".join(body) + "\n</body></html>\n")
