"""Shared matplotlib set-up: a headless backend, one colour per estimator, saving figures."""

import matplotlib

matplotlib.use("Agg")  # headless: no display on CI machines

import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

DPI = 110
_PALETTE = plt.get_cmap("tab10").colors
_LINESTYLES = ["-", "--", ":", "-."]


class EstimatorColours:
    """The same colour for an estimator in every figure of a page, in order of appearance."""

    def __init__(self):
        self._colours = {}

    def __call__(self, estimator):
        if estimator not in self._colours:
            self._colours[estimator] = _PALETTE[len(self._colours) % len(_PALETTE)]
        return self._colours[estimator]


def linestyle(k):
    return _LINESTYLES[k % len(_LINESTYLES)]


def save(fig, path):
    """Writes the figure as PNG and closes it (figures are many on a large suite)."""
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)
    return path


def new_figure(columns, rows=1, width=5.2, height=3.8):
    fig, axes = plt.subplots(rows, columns, figsize=(width * columns, height * rows),
                             squeeze=False)
    return fig, axes
