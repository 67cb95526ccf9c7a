"""The tile test's calibration (a `tile_calibration` report section) at a glance.

One panel per power curve (the bias in the brightest tile, the self-check's rule, and in the fixed
centre tile): the detection rate against k (the bias in multiples of the MDB), with 95% Wilson
intervals, for a bias of k × each seed's own reported MDB (circles) and for a fixed bias k × the
median MDB (squares), with the power predicted for each (lines). Last panel: each size row's
family-wise false-alarm rate with its 95% Wilson interval against α and the central 95% band of
Binomial(seeds, α) / seeds: Holm is conservative, so a correct test sits at or below α.
"""

import math

from figure_style import new_figure, save
from report_view import number


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


def _errorbar(ax, xs, block, label, marker, colour, offset):
    """The injected tile's own detection rate (what the prediction is for) with its Wilson
    interval, and the comparison's (which the other tiles' false alarms raise a little) hollow."""
    xs = [x + offset for x in xs]
    rates = [number(b.get("tile_detection_rate")) for b in block]
    low = [max(0.0, r - number(b.get("tile_wilson_low"))) for r, b in zip(rates, block)]
    high = [max(0.0, number(b.get("tile_wilson_high")) - r) for r, b in zip(rates, block)]
    ax.errorbar(xs, rates, yerr=[low, high], fmt=marker, color=colour, capsize=3, label=label)
    ax.scatter(xs, [number(b.get("detection_rate")) for b in block], marker=marker,
               facecolors="none", edgecolors=colour, s=40, label=label + ": the comparison")


def _power_panel(ax, curve):
    points = curve.get("points") or []
    xs = [number(p["multiplier"]) for p in points]
    own = [p["own_mdb"] for p in points]
    fixed = [p["fixed_bias"] for p in points]
    _errorbar(ax, xs, own, "k × each seed's own MDB", "o", "tab:blue", -0.02)
    ax.plot(xs, [number(b.get("predicted_power")) for b in own], color="tab:blue",
            label="predicted: t, statistic shifted by k·m")
    _errorbar(ax, xs, fixed, "fixed k × median MDB", "s", "tab:orange", 0.02)
    ax.plot(xs, [number(b.get("predicted_power")) for b in fixed], color="tab:orange",
            linestyle="--", label="predicted: noncentral t, RMS se")
    ax.axhline(0.8, color="grey", linestyle=":", linewidth=0.8, label="nominal power 0.8")
    ax.set_xlim(left=0.0)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("injected bias / MDB (k)")
    ax.set_ylabel("detection rate of the injected tile (95% Wilson)")
    rule = curve.get("tile_rule")
    where = "brightest tile (self-check rule)" if rule == "brightest" else "centre tile (fixed)"
    statistic = number(curve.get("mean_statistic"))
    ax.set_title(f"{curve['scene']} {curve['estimator_a']} vs {curve['estimator_b']}: bias in the "
                 f"{where}\nmean statistic before the bias "
                 f"{statistic if statistic is None else round(statistic, 3)}", fontsize=8)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6, loc="lower right")


def _size_panel(ax, rows, alpha):
    if not rows:
        ax.set_axis_off()
        return
    labels = []
    for i, row in enumerate(rows):
        rate = number(row.get("false_alarm_rate"))
        # Rounding can put an interval's end a hair inside the rate (at 0 alarms, say).
        low = max(0.0, rate - number(row.get("wilson_low")))
        high = max(0.0, number(row.get("wilson_high")) - rate)
        colour = "tab:red" if row.get("biased") else ("tab:green" if row.get("pass") else "black")
        ax.errorbar([i], [rate], yerr=[[low], [high]], fmt="o", color=colour, capsize=3)
        labels.append(f"{row['scene']}\n{row['estimator_a']} vs {row['estimator_b']}")
    seeds = max(int(row.get("seeds") or 1) for row in rows)
    band_low, band_high = binomial_band(seeds, alpha)
    ax.axhspan(band_low, band_high, color="grey", alpha=0.2,
               label=f"95% of Binomial({seeds}, α) / {seeds}")
    ax.axhline(alpha, color="grey", linestyle="--", linewidth=0.8, label=f"α = {alpha:g}")
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels(labels, fontsize=7)
    top = max(number(row.get("wilson_high")) or 0.0 for row in rows)
    ax.set_ylim(0.0, max(3.0 * alpha, min(1.0, 1.1 * top)))
    ax.set_ylabel("family-wise false-alarm rate (95% Wilson)")
    ax.set_title("tile test size (green: passes; red: a negative control)", fontsize=9)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")


def tile_calibration_figure(section, path):
    curves = section.get("power_curves") or []
    fig, axes = new_figure(len(curves) + 1, width=5.0, height=4.2)
    for ax, curve in zip(axes[0], curves):
        _power_panel(ax, curve)
    _size_panel(axes[0][len(curves)], section.get("rows") or [],
                number(section.get("test_alpha")) or 0.05)
    return save(fig, path)
