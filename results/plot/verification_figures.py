"""The suite's tests at a glance: z-scores per run, p-values against the uniform, power.

z is the signed normal quantile of each run's raw two-sided p-value (so Student t tests with
few degrees of freedom sit on the same scale as Welch and z tests). Under the null the p-values
of honest runs are uniform: the QQ plot shows them with the 95% Kolmogorov–Smirnov band. The
power curves are the report's tests' own: for a run with standard error se tested at the
threshold α it applied, the chance to flag a bias δ is Φ(δ/se − z) + Φ(−δ/se − z) with
z = Φ⁻¹(1 − α/2); a calibration report has measured detection rates instead, drawn with them.
"""

import math
from statistics import NormalDist

from figure_style import new_figure, save
from report_view import VERDICT_COLOURS, field, number, result_of

_NORMAL = NormalDist()


def signed_z(run):
    p = number(field(run, "verdict", "p_value"))
    t = number(field(run, "verdict", "statistic"))
    if p is None or t is None:
        return None
    p = min(max(p, 1e-300), 1.0)
    z = _NORMAL.inv_cdf(1.0 - p / 2.0) if p < 1.0 else 0.0
    return math.copysign(z, t)


def tested_runs(runs):
    return [r for r in runs if signed_z(r) is not None]


def _z_panel(ax, runs):
    tested = tested_runs(runs)
    if not tested:
        ax.text(0.5, 0.5, "no tested runs", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return
    for i, run in enumerate(tested):
        controls = field(run, "verdict", "expect") == "biased"
        z = signed_z(run)
        ax.scatter([i], [max(min(z, 40.0), -40.0)], color=VERDICT_COLOURS.get(result_of(run)),
                   marker="x" if controls else "o", s=18)
    alphas = [number(field(r, "verdict", "alpha")) for r in tested]
    smallest = min(a for a in alphas if a) if any(alphas) else None
    if smallest:
        z = _NORMAL.inv_cdf(1.0 - smallest / 2.0)
        for sign in (1, -1):
            ax.axhline(sign * z, color="grey", linestyle="--", linewidth=0.8)
    ax.set_xlabel("run (report order); × = negative control")
    ax.set_ylabel("signed z of the raw p-value (clipped at ±40)")
    ax.set_title("z-scores per run (dashed: the strictest Holm threshold)", fontsize=9)
    ax.grid(True, alpha=0.3)


def _qq_panel(ax, runs):
    ps = sorted(number(field(r, "verdict", "p_value")) for r in tested_runs(runs)
                if field(r, "verdict", "expect") == "consistent")
    if len(ps) < 2:
        ax.text(0.5, 0.5, "fewer than 2 honest tested runs", ha="center", va="center",
                transform=ax.transAxes)
        ax.set_axis_off()
        return
    n = len(ps)
    _uniform_qq_axes(ax, n, "raw p-value", "p-values of honest runs against the uniform")
    ax.scatter(_uniform_quantiles(n), ps, s=10, color=VERDICT_COLOURS["consistent"],
               label=f"{n} honest runs")
    ax.legend(fontsize=7, loc="upper left")


def _uniform_quantiles(n):
    return [(i + 0.5) / n for i in range(n)]


def _uniform_qq_axes(ax, n, ylabel, title):
    """The frame of a QQ plot against the uniform: the diagonal and the 95% Kolmogorov–Smirnov
    band for n points (1.358 / √n, the large-n critical distance)."""
    band = 1.358 / math.sqrt(n)
    ax.fill_between([0, 1], [-band, 1 - band], [band, 1 + band], color="grey", alpha=0.2,
                    label=f"95% KS band (n = {n})")
    ax.plot([0, 1], [0, 1], color="black", linewidth=0.8)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_xlabel("uniform quantile")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)


def predicted_power(bias, stderr, alpha):
    z = _NORMAL.inv_cdf(1.0 - alpha / 2.0)
    d = bias / stderr
    return _NORMAL.cdf(d - z) + _NORMAL.cdf(-d - z)


def _power_panel(ax, runs, calibration):
    if calibration and field(calibration, "power", "points"):
        points = calibration["power"]["points"]
        xs = [p["relative_bias"] for p in points]
        rate = [p["detection_rate"] for p in points]
        low = [p["detection_rate"] - p["wilson_low"] for p in points]
        high = [p["wilson_high"] - p["detection_rate"] for p in points]
        ax.errorbar(xs, rate, yerr=[low, high], fmt="o", capsize=3, label="detected (Wilson 95%)")
        ax.plot(xs, [p["predicted_power"] for p in points], label="predicted")
        ax.set_title(f"power curve ({calibration['power'].get('estimator', '')}, measured)",
                     fontsize=9)
        ax.set_xlabel("injected bias / reference")
    else:
        drawn = 0
        for run in tested_runs(runs):
            se = number(field(run, "aggregates", "stderr"))
            alpha = number(field(run, "verdict", "alpha"))
            scale = number(field(run, "aggregates", "mean_abs"))
            if not se or not alpha or not scale or field(run, "verdict", "expect") != "consistent":
                continue
            xs = [10 ** (k / 20.0) for k in range(-100, 1)]  # 1e-5 .. 1 of ∫|f|
            ax.plot(xs, [predicted_power(x * scale, se, alpha) for x in xs],
                    color=VERDICT_COLOURS["consistent"], alpha=0.25, linewidth=0.8)
            drawn += 1
        if not drawn:
            ax.text(0.5, 0.5, "no honest tested runs", ha="center", va="center",
                    transform=ax.transAxes)
            ax.set_axis_off()
            return
        ax.axhline(0.8, color="grey", linestyle="--", linewidth=0.8, label="80%")
        ax.set_title(f"power of each honest run's test ({drawn} runs)", fontsize=9)
        ax.set_xlabel("bias / ∫|f|")
    ax.set_xscale("log")
    ax.set_ylim(-0.02, 1.02)
    ax.set_ylabel("probability of flagging")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")


def has_tests(report):
    return bool(tested_runs(report.get("runs") or [])) or bool(report.get("calibration"))


def verification_figure(report, path):
    fig, axes = new_figure(3, width=5.0, height=4.0)
    runs = report.get("runs") or []
    _z_panel(axes[0][0], runs)
    _qq_panel(axes[0][1], runs)
    _power_panel(axes[0][2], runs, report.get("calibration"))
    return save(fig, path)


def calibration_qq_figure(calibration, path):
    """Per estimator of a calibration report: its p-values over seeds against the uniform."""
    estimators = [e for e in calibration.get("estimators") or [] if e.get("p_values")]
    if not estimators:
        return None
    fig, axes = new_figure(1, width=5.0, height=4.0)
    ax = axes[0][0]
    _uniform_qq_axes(ax, max(len(e["p_values"]) for e in estimators), "p-value over seeds",
                     "calibration: p-values against the uniform")
    for e in estimators:
        ps = sorted(p for p in e["p_values"] if number(p) is not None)
        ax.plot(_uniform_quantiles(len(ps)), ps, marker=".", markersize=3, linewidth=0.8,
                label=f"{e['estimator']} (KS p {e.get('ks_p_value', float('nan')):.2g})")
    ax.legend(fontsize=7, loc="upper left")
    return save(fig, path)
