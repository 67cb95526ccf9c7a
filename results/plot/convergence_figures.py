"""Per integrand: RMSE against samples and against CPU seconds, and efficiency with intervals.

The series are the report's: each run records, at every power of two of the sample count, the
RMSE of its replicates' running estimates and the CPU seconds spent by then. The band is the 95%
interval of that RMSE from its R replicates (R·RMSE²/σ² ~ χ²_R), drawn with the Wilson–Hilferty
quantiles so that no statistics library is needed beyond the standard one.
"""

import math
from statistics import NormalDist

from figure_style import linestyle, new_figure, save
from report_view import field, labels, number



def chi2_quantile(p, dof):
    """Wilson–Hilferty approximation of the chi-square quantile (good to ~1% for dof >= 3)."""
    z = NormalDist().inv_cdf(p)
    a = 2.0 / (9.0 * dof)
    return dof * max(1.0 - a + z * math.sqrt(a), 1e-6) ** 3


def rmse_band(rmse, replicates):
    """95% interval of an RMSE measured over `replicates` independent replicates."""
    if replicates < 2:
        return rmse, rmse
    low = rmse * math.sqrt(replicates / chi2_quantile(0.975, replicates))
    high = rmse * math.sqrt(replicates / chi2_quantile(0.025, replicates))
    return low, high


def series_points(run):
    """(samples, cpu_seconds, rmse) of the run's series where all three are finite; the
    replicates' spread (stderr·√R) stands in for the RMSE where the run has no reference."""
    replicates = len(run.get("replicates") or [])
    points = []
    for p in run.get("series") or []:
        rmse = number(p.get("rmse"))
        if rmse is None and number(p.get("stderr")) is not None:
            rmse = p["stderr"] * math.sqrt(max(replicates, 1))
        n, cpu = number(p.get("samples")), number(p.get("cpu_seconds"))
        if rmse is not None and rmse > 0 and n and cpu and cpu > 0:
            points.append((n, cpu, rmse))
    return points, replicates


def has_series(runs):
    return any(len(series_points(r)[0]) >= 2 for r in runs)


def _reference_slope(ax, xs, ys):
    """A dotted −1/2 line through the first point of the lowest curve, for the eye."""
    x0, y0 = xs[0], ys[0]
    x1 = xs[-1]
    ax.plot([x0, x1], [y0, y0 * math.sqrt(x0 / x1)], color="black", linestyle=":", linewidth=1,
            label="slope −1/2")


def _efficiency_bars(ax, runs, names, colours):
    values, lows, highs, bar_colours, bar_names = [], [], [], [], []
    for run, name in zip(runs, names):
        eff = number(field(run, "aggregates", "efficiency"))
        if eff is None or eff <= 0:
            continue
        low = number(field(run, "aggregates", "efficiency_low")) or eff
        high = number(field(run, "aggregates", "efficiency_high")) or eff
        values.append(eff)
        lows.append(max(eff - low, 0.0))
        highs.append(max(high - eff, 0.0))
        bar_colours.append(colours(run["estimator"]))
        bar_names.append(name)
    if not values:
        ax.text(0.5, 0.5, "no efficiency in the report", ha="center", va="center",
                transform=ax.transAxes)
        ax.set_axis_off()
        return
    ys = list(range(len(values)))
    ax.barh(ys, values, xerr=[lows, highs], color=bar_colours, alpha=0.85, capsize=3)
    ax.set_yticks(ys, bar_names, fontsize=7)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlabel("efficiency 1/(variance × s per sample), 95% interval")
    ax.grid(True, axis="x", which="both", alpha=0.3)


def convergence_figure(group_name, runs, colours, path):
    """Three panels for one integrand: RMSE vs samples, RMSE vs CPU seconds, efficiency."""
    fig, axes = new_figure(3, width=5.0, height=4.0)
    by_samples, by_seconds, efficiency = axes[0]
    names = labels(runs)
    per_estimator = {}
    lowest = None
    for run, name in zip(runs, names):
        points, replicates = series_points(run)
        if len(points) < 2:
            continue
        k = per_estimator.get(run["estimator"], 0)
        per_estimator[run["estimator"]] = k + 1
        ns, cpus, rmses = zip(*points)
        band = [rmse_band(r, replicates) for r in rmses]
        style = {"color": colours(run["estimator"]), "linestyle": linestyle(k), "linewidth": 1.3}
        slope = number(field(run, "aggregates", "rmse_slope"))
        label = name + (f" (slope {slope:.2f})" if slope is not None else "")
        for ax, xs in ((by_samples, ns), (by_seconds, cpus)):
            ax.plot(xs, rmses, label=label, **style)
            ax.fill_between(xs, [b[0] for b in band], [b[1] for b in band],
                            color=style["color"], alpha=0.12 if len(runs) <= 4 else 0.05, linewidth=0)
        if lowest is None or rmses[0] < lowest[1][0]:
            lowest = (ns, rmses)
    if lowest:
        _reference_slope(by_samples, *lowest)
    for ax, xlabel in ((by_samples, "samples per replicate"),
                       (by_seconds, "CPU seconds per replicate")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("RMSE across replicates (95% band)")
        ax.grid(True, which="both", alpha=0.3)
    by_samples.set_title(f"{group_name}: RMSE against samples", fontsize=9)
    by_seconds.set_title("RMSE against time", fontsize=9)
    handles, names_shown = by_samples.get_legend_handles_labels()
    if handles:  # below the panels: a suite's many runs would hide the curves
        fig.legend(handles, names_shown, fontsize=7, loc="upper center", ncol=3,
                   bbox_to_anchor=(0.5, 0.0), frameon=False)
    _efficiency_bars(efficiency, runs, names, colours)
    efficiency.set_title("efficiency", fontsize=9)
    return save(fig, path)
