"""The module's functions: each builds the command line's request and runs the C++ harness
(the extension _pcbench) on it, so the numbers are the CLI's."""

import builtins
import json
import math
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import pandas as pd

from . import _pcbench
from ._reports import report_tables

# The CLI's exit statuses (docs/reference/INTERFACE.md, "Exit status").
_EXIT_OK, _EXIT_VERDICT_DIFFERS, _EXIT_BAD_INPUT, _EXIT_RUN_FAILED, _EXIT_INTERRUPTED = (
    0, 1, 2, 3, 130)

_SCALE_COLUMNS = ["block", "columns", "rows", "tests", "bright_tests", "blocks_differing",
                  "relative_mdb", "required_mdb", "meets_requirement",
                  "samples_factor_for_required_mdb", "min_p_adjusted", "alpha_share"]


def _number(value):
    return math.nan if value is None else float(value)


@dataclass(frozen=True)
class ImageVerification:
    """What verify_images found.

    verdict: the comparison's result (consistent, biased, inconclusive, ...); expect: what it
    was expected to be; as_expected: the comparison and every self-check (twice the detectable
    bias planted in one block per scale, expected biased) came out as expected, which is when
    the CLI exits 0; reason: the verdict in words; p_adjusted: the comparison's Holm-adjusted p
    (the smallest over its blocks); scales: one row per scale of the block pyramid, the tiles
    first and the whole image last (block edge in pixels, tests, blocks_differing: how many
    block x channel tests differ, relative_mdb: the largest detectable bias relative to a bright
    block's mean, required_mdb and samples_factor_for_required_mdb: (relative_mdb /
    required_mdb)^2, the samples needed to meet it); report: the whole report as the CLI writes
    it (a dict); out: the folder it was written to, or None.
    """

    verdict: str
    expect: str
    as_expected: bool
    reason: str
    p_adjusted: float
    scales: pd.DataFrame = field(repr=False)
    report: dict = field(repr=False)
    out: Optional[str] = None

    @property
    def comparison(self):
        """The report's comparison entry (a dict); self_checks holds the others."""
        return self.report["comparisons"][0]

    @property
    def self_checks(self):
        """The self-checks' comparison entries (dicts), one per scale."""
        return self.report["comparisons"][1:]


@dataclass(frozen=True)
class EstimatesVerification:
    """What verify_estimates found: the verdict (consistent, biased, inconclusive, untested),
    expect, as_expected, reason, the test's statistic (t), p_value, p_adjusted,
    min_detectable_bias (80% power), the estimates' mean, tail_shape (NaN under 50 replicates),
    report (the CLI's report, a dict) and out (the folder it was written to, or None)."""

    verdict: str
    expect: str
    as_expected: bool
    reason: str
    statistic: float
    p_value: float
    p_adjusted: float
    min_detectable_bias: float
    mean: float
    tail_shape: float
    report: dict = field(repr=False)
    out: Optional[str] = None


@dataclass(frozen=True)
class SessionResult:
    """What run and verify return: report (the CLI's report.json as a dict), out (the folder
    it was written to, or None when it went to a temporary folder since removed), exit_status
    (the CLI's: 0, or 1 when a verdict differs from its expectation), and the report's runs and
    comparisons as DataFrames (read_report's columns)."""

    report: dict = field(repr=False)
    out: Optional[str] = None
    exit_status: int = 0

    @property
    def runs(self):
        """One row per run (read_report's columns)."""
        return report_tables(self.report).runs

    @property
    def comparisons(self):
        """One row per comparison (read_report's columns)."""
        return report_tables(self.report).comparisons


def _side(value, name):
    """A set as the extension takes it: a SET of files (str: a file list, folder or glob, as
    the CLI's --images) or an array."""
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    if isinstance(value, (builtins.list, tuple)) and value and all(
            isinstance(v, (str, os.PathLike)) for v in value):
        return ",".join(os.fspath(v) for v in value)
    array = np.asarray(value)
    if array.dtype == object:
        raise ValueError(f"{name}: give an array (R, H, W, C) or a list of image paths")
    return array


def verify_images(a, *, against=None, reference=None, reference_stderr=None, constant=None,
                  alpha=0.01, tile=8, channels=None, paired=False, expect="consistent",
                  out=None, verbose=False):
    """Test replicate images for bias, block by block, as ``pcbench verify --images``.

    a: R >= 2 independent replicate images (one seed each) as a numpy array of shape
       (R, H, W, C), float32 or float64 (C = 1 is tested as grey; C >= 3 takes channels 0, 1,
       2), or image files: a list of paths, a folder or a glob (EXR, HDR or PFM).
    Exactly one of what it is tested against:
      against: a second independent set, the same kinds (Welch per block; with paired=True,
               replicate k of both sets from the same seed, the paired t on differences);
      reference: a converged image (H, W, C) or (H, W), or a file, with reference_stderr its
               per-pixel standard error (without it the reference is taken as exact);
      constant: an exact value, V or (R, G, B) (a furnace).
    alpha: the family-wise false-alarm rate; tile: the finest block's edge in pixels;
    channels: three channel indices (arrays) or names (files) that fill R, G, B;
    expect: "consistent" or "biased" (a set with a known bias); out: a folder to write the
    report and the mean, standard error and z-map EXR images into, as the CLI does (nothing is
    written without it); verbose: print the verdicts as the CLI does.

    Returns an ImageVerification (verdict, reason, p_adjusted, scales, report, ...), whose
    numbers equal the CLI's on the same data written as float EXR, to the bit. Raises
    ValueError for bad input (shapes, dtype, R < 2, a NaN or inf located by replicate and
    pixel, two identical replicates, not exactly one of against/reference/constant), with the
    CLI's message, before anything is written.
    """
    against_side = None if against is None else _side(against, "against")
    reference_side = None if reference is None else _side(reference, "reference")
    stderr_side = None if reference_stderr is None else _side(reference_stderr,
                                                              "reference_stderr")
    constant_text = None
    if constant is not None:
        values = np.atleast_1d(np.asarray(constant, dtype=np.float64))
        constant_text = ",".join(repr(float(v)) for v in values)
    found = _pcbench._verify_images(
        _side(a, "a"), against_side, reference_side, stderr_side, constant_text, float(alpha),
        int(tile), None if channels is None else builtins.list(channels), bool(paired),
        str(expect), None if out is None else os.fspath(out), bool(verbose))
    report = json.loads(found["report"])
    comparison = report["comparisons"][0]
    scales = pd.DataFrame(
        [{**{k: scale.get(k) for k in _SCALE_COLUMNS},
          "blocks_differing": len(scale["blocks_differing"])}
         for scale in comparison["scales"]], columns=_SCALE_COLUMNS)
    for column in ("relative_mdb", "required_mdb", "samples_factor_for_required_mdb",
                   "min_p_adjusted", "alpha_share"):
        scales[column] = scales[column].map(_number).astype(float)
    if verbose and found["warnings"]:
        print(found["warnings"], end="")
    return ImageVerification(
        verdict=comparison["result"], expect=comparison["expect"],
        as_expected=bool(found["as_expected"]), reason=comparison.get("reason", ""),
        p_adjusted=_number(comparison["p_adjusted"]), scales=scales, report=report,
        out=found["out"])


def verify_estimates(x, *, reference=None, against=None, alpha=0.01, expect="consistent",
                     out=None, verbose=False):
    """Test replicate estimates of one quantity, as ``pcbench verify --estimates``.

    x: R >= 2 independent replicate estimates (a 1-D array), all finite. Exactly one of
    reference: the value to test against, V, (V, U) with U its standard uncertainty, or the
               CLI's text "V±U" (Student t, or Welch when U > 0);
    against: a second 1-D array of independent estimates (two-sample Welch).
    alpha: the family-wise false-alarm rate; expect: "consistent" or "biased"; out: a folder
    to write the report into (nothing is written without it); verbose: print the CLI's line.

    Returns an EstimatesVerification with the CLI's numbers to the bit. Raises ValueError for
    bad input (not 1-D, fewer than 2, a non-finite estimate named by its index, a malformed
    reference, not exactly one of reference and against).
    """
    def estimates(values, name):
        array = np.asarray(values, dtype=np.float64)
        if array.ndim != 1:
            raise ValueError(f"{name}: shape {array.shape}; give a 1-D array of estimates")
        return array.tolist()

    reference_text = None
    if reference is not None:
        if isinstance(reference, str):
            reference_text = reference
        elif np.ndim(reference) == 0:
            reference_text = repr(float(reference))
        else:
            value, uncertainty = (float(v) for v in reference)
            reference_text = f"{value!r}+-{uncertainty!r}"
    found = _pcbench._verify_estimates(
        estimates(x, "x"), None if against is None else estimates(against, "against"),
        reference_text, float(alpha), str(expect), None if out is None else os.fspath(out),
        bool(verbose))
    report = json.loads(found["report"])
    entry = report["external"][0]
    verdict = entry["verdict"]
    if verbose:
        print(f"{entry['replicates']} estimates: mean {entry['mean']:.6g}; {verdict['result']} "
              f"({verdict['reason']}); minimum detectable bias "
              f"{_number(verdict['min_detectable_bias']):.3g}")
    return EstimatesVerification(
        verdict=verdict["result"], expect=verdict["expect"],
        as_expected=bool(found["as_expected"]), reason=verdict["reason"],
        statistic=_number(verdict["statistic"]), p_value=_number(verdict["p_value"]),
        p_adjusted=_number(verdict["p_adjusted"]),
        min_detectable_bias=_number(verdict["min_detectable_bias"]),
        mean=_number(entry["mean"]), tail_shape=_number(entry["tail_shape"]), report=report,
        out=found["out"])


def _cli(args, verbose):
    """Runs the CLI in this process; its stdout, or ValueError / RuntimeError for its
    statuses 2 and 3 (KeyboardInterrupt comes from the extension on Ctrl-C)."""
    status, printed, errors = _pcbench._cli([str(a) for a in args], bool(verbose))
    if verbose and errors:
        print(errors, end="")
    if status == _EXIT_BAD_INPUT:
        lines = [line.removeprefix("pcbench: error: ").removeprefix("command line: ")
                 for line in errors.splitlines() if line.startswith("pcbench: error: ")]
        raise ValueError("\n".join(lines) or errors.strip())
    if status == _EXIT_RUN_FAILED:
        raise RuntimeError(errors.strip() or "pcbench: the report could not be written")
    if status == _EXIT_INTERRUPTED:
        raise KeyboardInterrupt
    return status, printed


def _comma(values):
    if isinstance(values, str):
        return values
    return ",".join(str(v) for v in values)


def _selection_args(suite, estimators, integrands, params, samples, seconds, replicates, seed,
                    threads, interleave, paired, require_mdb):
    args = []
    if suite is not None:
        args.append(os.fspath(suite))
    if estimators is not None:
        args += ["--estimator", _comma(estimators)]
    if integrands is not None:
        args += ["--integrand", _comma(integrands)]
    if params:
        items = params.items() if isinstance(params, dict) else (p.split("=", 1) for p in params)
        for key, value in items:
            text = value if isinstance(value, str) else (
                _comma(value) if np.ndim(value) else str(value))
            args += ["--param", f"{key}={text}"]
    for flag, value in (("--samples", samples), ("--seconds", seconds),
                        ("--replicates", replicates), ("--seed", seed), ("--threads", threads)):
        if value is not None:
            args += [flag, str(value)]
    if interleave:
        args.append("--interleave")
    if paired:
        args.append("--paired")
    for key, value in (require_mdb or {}).items():
        args += ["--require-mdb", f"{key}={value}"]
    return args


def _session(command, args, out, verbose):
    """Runs `pcbench COMMAND ARGS` with --out (a temporary folder when out is None) and reads
    back its report."""
    folder = os.fspath(out) if out is not None else tempfile.mkdtemp(prefix="pcbench-")
    try:
        args = [command, *args, "--out", folder] + ([] if verbose else ["--quiet"])
        status, _ = _cli(args, verbose)
        with open(os.path.join(folder, "report.json"), encoding="utf-8") as file:
            report = json.load(file)
    finally:
        if out is None:
            shutil.rmtree(folder, ignore_errors=True)
    return SessionResult(report=report, out=None if out is None else folder, exit_status=status)


def run(suite=None, *, estimators=None, integrands=None, params=None, samples=None,
        seconds=None, replicates=None, seed=None, threads=None, interleave=False, paired=False,
        require_mdb=None, out=None, verbose=False):
    """Run a suite file or a selection, as ``pcbench run``; returns a SessionResult.

    suite: a suite file (or give estimators and integrands: names, or lists of names, a grid);
    params: {"M": [1, 4, 16], "resolution": 16} or ["M=1,4,16"] (--param; a list is a grid);
    samples (per replicate; per pixel on scenes) or seconds (equal time), replicates, seed,
    threads: as the CLI's options; interleave, paired, require_mdb ({"tile": 0.05}): likewise.
    out: the folder of the report (and images); without it the report goes to a temporary
    folder that is removed once read. verbose: the CLI's summary table as it prints it, and
    what it wrote on stderr (warnings) once it returns; quiet otherwise.

    The run executes without the GIL; Ctrl-C stops it as it stops the command (the report of
    the finished runs is written into out) and raises KeyboardInterrupt. Raises ValueError for
    bad input (an unknown estimator names the nearest ones) before anything runs or is
    written, RuntimeError when the report cannot be written.
    """
    args = _selection_args(suite, estimators, integrands, params, samples, seconds, replicates,
                           seed, threads, interleave, paired, require_mdb)
    return _session("run", args, out, verbose)


def verify(suite=None, *, estimators=None, integrands=None, params=None, samples=None,
           seconds=None, replicates=None, seed=None, threads=None, interleave=False,
           paired=False, require_mdb=None, alpha=0.01, exact=False, out=None, verbose=False):
    """Verify a suite file or a selection, as ``pcbench verify``; returns a SessionResult.

    The options are run's, with alpha (family-wise) and exact (enumerate the resampling step,
    ``--exact``). A negative control alone (estimators=["ctl-wrong-count"], no integrands)
    runs on its declared workload. Errors and Ctrl-C as for run.
    """
    args = _selection_args(suite, estimators, integrands, params, samples, seconds, replicates,
                           seed, threads, interleave, paired, require_mdb)
    args += ["--alpha", repr(float(alpha))]
    if exact:
        args.append("--exact")
    return _session("verify", args, out, verbose)


def list():  # noqa: A001 (the CLI's name)
    """The catalogue, as ``pcbench list --json``: a dict of the estimators (each with its
    parameters, types, defaults and descriptions, a negative control's declared workload) and
    the integrands and scenes."""
    _, printed = _cli(["list", "--json"], False)
    return json.loads(printed)
