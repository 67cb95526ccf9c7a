"""The block pyramid's calibration (a `tile_calibration` report section) at a glance.

One panel per compared pair and block rule (the bias in the brightest block of each scale, the
self-check's rule, and in the fixed centre block): per scale, the injected block's own detection
rate against k (the bias in multiples of its reported MDB) with 95% Wilson intervals (filled) and
the pyramid's (hollow), with the power predicted for the block (lines). Last panel: each size
row's family-wise false-alarm rate over the whole pyramid and through each scale, with 95% Wilson
intervals, against α and against a scale's share α / L, and the central 95% band of
Binomial(seeds, α) / seeds: Holm is conservative, so a correct test sits at or below α, each
scale at or below about α / L.
"""

import math

from figure_style import new_figure, save
from report_view import number

COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink",
           "tab:cyan", "tab:olive"]


def binomial_band(n, p, level=0.95):
    """The central `level` range of Binomial(n, p) / n (each tail at most (1 - level) / 2)."""
    tail = (1.0 - level) / 2.0
    pmf = [math.comb(n, k) * p ** k * (1.0 - p) ** (n - k) for k in range(n + 1)]
    low, total = 0, 0.0
    while low < n and total + pmf[low] <= tail:
        total += pmf[low]
        low += 1
    high, total = n, 0.0
    while high > 0 and total + pmf[high] <= tail:
        total += pmf[high]
        high -= 1
    return low / n, high / n


def _curve_series(ax, curve, colour, offset):
    """One scale's curve: the block's own detections (what the prediction is for) with its Wilson
    interval, the pyramid's hollow, the prediction as a line."""
    points = curve.get("points") or []
    xs = [number(p["multiplier"]) + offset for p in points]
    rates = [number(p.get("block_detection_rate")) for p in points]
    low = [max(0.0, r - number(p.get("block_wilson_low"))) for r, p in zip(rates, points)]
    high = [max(0.0, number(p.get("block_wilson_high")) - r) for r, p in zip(rates, points)]
    label = f"{curve.get('block')} px"
    ax.errorbar(xs, rates, yerr=[low, high], fmt="o", color=colour, capsize=3,
                label=label + ": the block")
    ax.scatter(xs, [number(p.get("detection_rate")) for p in points], marker="o",
               facecolors="none", edgecolors=colour, s=40, label=label + ": the pyramid")
    ax.plot([number(p["multiplier"]) for p in points],
            [number(p.get("predicted_power")) for p in points], color=colour, linewidth=0.8,
            label=label + ": predicted")


def _power_panel(ax, group):
    first = group[0]
    for i, curve in enumerate(group):
        _curve_series(ax, curve, COLOURS[i % len(COLOURS)], 0.02 * (i - (len(group) - 1) / 2))
    ax.axhline(0.8, color="grey", linestyle=":", linewidth=0.8, label="nominal power 0.8")
    ax.set_xlim(left=0.0)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("injected bias / the block's MDB (k)")
    ax.set_ylabel("detection rate (95% Wilson)")
    rule = first.get("block_rule")
    where = "brightest block (self-check rule)" if rule == "brightest" else "centre block (fixed)"
    ax.set_title(f"{first['scene']} {first['estimator_a']} vs {first['estimator_b']}: bias in "
                 f"the {where} of each scale", fontsize=8)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=5, loc="lower right", ncol=2)


def _groups(curves):
    """The curves by (pair, rule), in report order."""
    groups = []
    for curve in curves:
        key = (curve.get("scene"), curve.get("run_a"), curve.get("run_b"), curve.get("block_rule"))
        if groups and groups[-1][0] == key:
            groups[-1][1].append(curve)
        else:
            groups.append((key, [curve]))
    return [g for _, g in groups]


def _rate_point(ax, x, entry, colour, marker):
    rate = number(entry.get("false_alarm_rate"))
    # Rounding can put an interval's end a hair inside the rate (at 0 alarms, say).
    low = max(0.0, rate - number(entry.get("wilson_low")))
    high = max(0.0, number(entry.get("wilson_high")) - rate)
    ax.errorbar([x], [rate], yerr=[[low], [high]], fmt=marker, color=colour, capsize=3)


def _size_panel(ax, rows, alpha):
    if not rows:
        ax.set_axis_off()
        return
    labels, ticks, x = [], [], 0.0
    for row in rows:
        colour = "tab:red" if row.get("biased") else ("tab:green" if row.get("pass") else "black")
        _rate_point(ax, x, row, colour, "o")
        ticks.append(x)
        labels.append(f"{row['scene']}\n{row['estimator_a']} vs {row['estimator_b']}")
        for s, scale in enumerate(row.get("scales") or []):
            _rate_point(ax, x + 0.15 * (s + 1), scale, colour, "s")
        x += 1.0
    seeds = max(int(row.get("seeds") or 1) for row in rows)
    levels = max(len(row.get("scales") or [None]) for row in rows)
    band_low, band_high = binomial_band(seeds, alpha)
    ax.axhspan(band_low, band_high, color="grey", alpha=0.2,
               label=f"95% of Binomial({seeds}, α) / {seeds}")
    ax.axhline(alpha, color="grey", linestyle="--", linewidth=0.8, label=f"α = {alpha:g}")
    ax.axhline(alpha / levels, color="grey", linestyle=":", linewidth=0.8,
               label=f"a scale's share α / L = {alpha / levels:.3g}")
    ax.set_xticks(ticks)
    ax.set_xticklabels(labels, fontsize=7)
    tops = [number(e.get("wilson_high")) or 0.0
            for row in rows for e in [row] + list(row.get("scales") or [])]
    ax.set_ylim(0.0, max(3.0 * alpha, min(1.0, 1.1 * max(tops))))
    ax.set_ylabel("false-alarm rate (95% Wilson)")
    ax.set_title("pyramid size: circles overall, squares through each scale, finest first\n"
                 "(green: passes; red: a negative control)", fontsize=8)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=6, loc="upper left")


def tile_calibration_figure(section, path):
    groups = _groups(section.get("power_curves") or [])
    fig, axes = new_figure(len(groups) + 1, width=5.0, height=4.2)
    for ax, group in zip(axes[0], groups):
        _power_panel(ax, group)
    _size_panel(axes[0][len(groups)], section.get("rows") or [],
                number(section.get("test_alpha")) or 0.05)
    return save(fig, path)
