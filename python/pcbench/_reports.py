"""Reading a pcbench report (results/report.schema.json) into pandas DataFrames."""

import json
import math
import os
from dataclasses import dataclass

import pandas as pd

# The schema versions this reader knows (results/report.schema.json, "schema_version").
_KNOWN_SCHEMA_VERSIONS = (1,)

_RUN_COLUMNS = [
    "id", "estimator", "integrand", "params", "status", "samples", "replicates", "mean",
    "stderr", "reference", "reference_kind", "bias", "bias_in_stderr", "rel_mse", "rmse",
    "cpu_seconds", "seconds_per_sample", "efficiency", "efficiency_low", "efficiency_high",
    "min_detectable_rel_bias", "p_adjusted", "verdict", "expect", "reason",
]

_COMPARISON_COLUMNS = [
    "a", "b", "estimator", "integrand", "test", "statistic", "p_value", "p_adjusted", "alpha",
    "mean_a", "mean_b", "stderr_a", "stderr_b", "min_detectable_difference",
    "tile_relative_mdb", "samples_factor_for_required_mdb", "requirements_met", "result",
    "expect", "reason",
]


@dataclass(frozen=True)
class Report:
    """A report read by read_report: ``runs`` and ``comparisons`` as DataFrames, ``data`` the
    whole report as a dict, ``path`` the file it was read from."""

    runs: pd.DataFrame
    comparisons: pd.DataFrame
    data: dict
    path: str

    def __iter__(self):
        """``runs, comparisons = read_report(path)`` unpacks the two tables."""
        return iter((self.runs, self.comparisons))


def _number(value):
    """A report number as a float; null (a non-finite number, or none) as NaN."""
    return math.nan if value is None else float(value)


def _run_row(run):
    aggregates = run.get("aggregates") or {}
    verdict = run.get("verdict") or {}
    reference = run.get("reference") or {}
    replicates = run.get("replicates") or []
    return {
        "id": run["id"],
        "estimator": run["estimator"],
        "integrand": run["integrand"],
        "params": dict(run.get("params") or {}),
        "status": run["status"],
        "samples": int(run["samples"]),
        "replicates": len(replicates),
        "mean": _number(aggregates.get("mean")),
        "stderr": _number(aggregates.get("stderr")),
        "reference": _number(reference.get("value")),
        "reference_kind": reference.get("kind", "none"),
        "bias": _number(aggregates.get("bias")),
        # The run test's t: (mean - reference) / its standard error.
        "bias_in_stderr": _number(verdict.get("statistic")),
        "rel_mse": _number(aggregates.get("rel_mse")),
        "rmse": _number(aggregates.get("rmse")),
        "cpu_seconds": math.fsum(_number(r.get("cpu_seconds")) for r in replicates),
        "seconds_per_sample": _number(aggregates.get("seconds_per_sample")),
        "efficiency": _number(aggregates.get("efficiency")),
        "efficiency_low": _number(aggregates.get("efficiency_low")),
        "efficiency_high": _number(aggregates.get("efficiency_high")),
        "min_detectable_rel_bias": _number(verdict.get("min_detectable_rel_bias")),
        "p_adjusted": _number(verdict.get("p_adjusted")),
        "verdict": verdict.get("result"),
        "expect": verdict.get("expect"),
        "reason": verdict.get("reason"),
    }


def _comparison_row(comparison):
    row = {}
    for column in _COMPARISON_COLUMNS:
        value = comparison.get(column)
        if column in ("a", "b") and isinstance(value, dict):
            value = value.get("id", json.dumps(value))
        if column in ("statistic", "p_value", "p_adjusted", "alpha", "mean_a", "mean_b",
                      "stderr_a", "stderr_b", "min_detectable_difference", "tile_relative_mdb",
                      "samples_factor_for_required_mdb"):
            value = _number(value)
        row[column] = value
    return row


def read_report(path):
    """Read a pcbench report into pandas DataFrames.

    ``path`` is a report.json, or a folder holding one (``results/latest``, an ``out=``
    folder). Returns a Report: ``runs`` (one row per run: estimator, integrand, params, mean,
    stderr, reference, bias, bias_in_stderr (the run test's t), rel_mse, cpu_seconds,
    efficiency with its 95% interval, min_detectable_rel_bias, p_adjusted, verdict, expect,
    reason, ...), ``comparisons`` (one row per two-sample comparison or image-set comparison)
    and ``data`` (the whole report). Unpacks as ``runs, comparisons = read_report(path)``.
    Null numbers of the report (non-finite, or undefined) are NaN. Raises ValueError for a file
    that is not a pcbench report, or of a schema version this reader does not know.
    """
    path = os.fspath(path)
    if os.path.isdir(path):
        path = os.path.join(path, "report.json")
    try:
        with open(path, encoding="utf-8") as file:
            data = json.load(file)
    except OSError as e:
        raise ValueError(f"{path}: cannot read the report: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}:{e.lineno}:{e.colno}: not JSON: {e.msg}") from None
    if not isinstance(data, dict) or "runs" not in data or "schema_version" not in data:
        raise ValueError(f"{path}: not a pcbench report (no \"schema_version\" and \"runs\")")
    if data["schema_version"] not in _KNOWN_SCHEMA_VERSIONS:
        raise ValueError(
            f"{path}: schema_version {data['schema_version']!r}; this reader knows "
            f"{', '.join(map(str, _KNOWN_SCHEMA_VERSIONS))}")
    return report_tables(data, path)


def report_tables(data, path=""):
    """The Report of a report already parsed (a dict, as run() and verify() return it)."""
    runs = pd.DataFrame([_run_row(r) for r in data.get("runs", [])], columns=_RUN_COLUMNS)
    comparisons = pd.DataFrame([_comparison_row(c) for c in data.get("comparisons", [])],
                               columns=_COMPARISON_COLUMNS)
    return Report(runs=runs, comparisons=comparisons, data=data, path=path)
