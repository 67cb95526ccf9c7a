"""Read-only views of a pcbench report for the plots and the page.

Everything here is looked up in the report as written: the plots never rerun or recompute the
experiment. Optional sections (series, images, comparisons, calibration) may be missing or
empty, and fields may be null (non-finite numbers are written as null by the report writer).
"""

import json
import math
import os


class ReportError(Exception):
    """The file is not a pcbench report this page can be made from (bad input)."""


VERDICT_COLOURS = {
    "consistent": "#2e7d32",
    "biased": "#c62828",
    "inconclusive": "#ef6c00",
    None: "#757575",
}


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
    except FileNotFoundError:
        raise ReportError(f"{path}: no such file")
    except json.JSONDecodeError as e:
        raise ReportError(f"{path}:{e.lineno}:{e.colno}: not JSON: {e.msg}")
    except (OSError, UnicodeDecodeError) as e:
        raise ReportError(f"{path}: cannot read: {e}")
    if not isinstance(report, dict) or "schema_version" not in report or "runs" not in report:
        raise ReportError(f"{path}: not a pcbench report (no schema_version or runs)")
    if report["schema_version"] != 1:
        raise ReportError(
            f"{path}: schema_version {report['schema_version']} is not supported (valid: 1)")
    return report


def number(value):
    """A finite float, or None (null, missing or non-finite)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def field(obj, *keys):
    """obj[k0][k1]..., or None where any level is missing or null."""
    for key in keys:
        if not isinstance(obj, dict) or obj.get(key) is None:
            return None
        obj = obj[key]
    return obj


def result_of(run):
    """The run's verdict ('consistent', 'biased', 'inconclusive'), or None when it was not
    tested (failed, not run, or a scene run without a scalar test)."""
    return field(run, "verdict", "result")


def expectation_of(run):
    return field(run, "verdict", "expect")


def matches_expectation(run):
    result = result_of(run)
    return result is not None and result == expectation_of(run)


def by_integrand(runs):
    """Runs grouped by integrand and its parameters, in the report's order. A group is named
    by its integrand, and by the parameters in which it differs from other groups of the same
    integrand (genz-gaussian light_dims=1, genz-gaussian light_dims=3)."""
    groups = {}
    for run in runs:
        key = (run["integrand"], tuple(sorted((k, str(v)) for k, v in
                                              integrand_params(run).items())))
        groups.setdefault(key, []).append(run)
    named = {}
    for (integrand, params), members in groups.items():
        others = [dict(p) for (i, p) in groups if i == integrand]
        varying = [(k, v) for k, v in params if len({o.get(k) for o in others}) > 1]
        named[" ".join([integrand] + [f"{k}={v}" for k, v in varying])] = members
    return named


def integrand_params(run):
    return run.get("integrand_params") or {}


def labels(runs):
    """A short label per run: its estimator, and the parameters in which it differs from other
    runs of the same estimator in `runs` (pcbpt M=4 K=1, pcbpt M=16 K=1, ...)."""
    out = []
    for run in runs:
        same = [r for r in runs if r["estimator"] == run["estimator"]]
        params = run.get("params") or {}
        varying = [k for k in params
                   if len({str((r.get("params") or {}).get(k)) for r in same}) > 1]
        out.append(" ".join([run["estimator"]] + [f"{k}={params[k]}" for k in varying]))
    return out


def is_scene(run):
    return isinstance(run.get("image"), dict)


def relative_link(report_dir, out_dir, name):
    """The path to a file named in the report (relative to its folder) from the plot folder."""
    return os.path.relpath(os.path.join(report_dir, name), out_dir).replace(os.sep, "/")
