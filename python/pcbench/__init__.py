"""pcbench from Python: the verifier and harness of pcbench, on numpy arrays and reports.

The numbers are the command line's to the bit: these functions call the same C++ code as
``pcbench verify`` and ``pcbench run`` (docs/guide/python.md, docs/reference/INTERFACE.md).

    verify_images(a, against=b)        replicate images (R, H, W, C) tested block by block
    verify_estimates(x, reference=v)   1-D replicate estimates, as ``verify --estimates``
    run(...), verify(...)              the CLI's runs and verifications; the report as a dict
    list()                             the estimators and integrands, as data
    read_report(path)                  a report's runs and comparisons as pandas DataFrames

Bad input raises ValueError with the command line's message; nothing is printed unless
``verbose=True``; nothing is written unless ``out=`` names a folder (``run`` and ``verify``
write into a temporary folder, removed afterwards, when it does not).
"""

from ._api import (
    EstimatesVerification,
    ImageVerification,
    list,  # noqa: A004 (the CLI's name)
    run,
    verify,
    verify_estimates,
    verify_images,
)
from ._api import SessionResult
from ._pcbench import _version
from ._reports import Report, read_report

__version__ = _version()

__all__ = [
    "EstimatesVerification",
    "ImageVerification",
    "Report",
    "SessionResult",
    "list",
    "read_report",
    "run",
    "verify",
    "verify_estimates",
    "verify_images",
]
