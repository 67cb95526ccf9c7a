"""Scenes: reference, estimate, relative error and z-map side by side, one row per run.

The images are the EXR files the report names (read with OpenImageIO from Debian's
python3-openimageio). The reference is the file the run was compared with (the exact image, or
the best-converged other run's mean). Estimate and reference share one exposure (the reference's
99th percentile maps to white) and a display gamma of 2.2; the relative error is
|estimate − reference| / (reference + 1% of its mean), averaged over RGB; the z-map shows, per
pixel, the channel with the largest |z|, clipped to ±4.
"""

import os

import numpy as np

from answer_view import tiles_marked
from figure_style import new_figure, save
from report_view import field, labels, number

try:
    import OpenImageIO as oiio
except ImportError:  # the page still shows everything else
    oiio = None


def read_exr(path):
    """An H×W×3 float array, or None when the file cannot be read."""
    if oiio is None or not os.path.isfile(path):
        return None
    image = oiio.ImageInput.open(path)
    if image is None:
        return None
    try:
        pixels = image.read_image(format=oiio.FLOAT)
    finally:
        image.close()
    if pixels is None:
        return None
    pixels = np.asarray(pixels, dtype=np.float64)
    if pixels.ndim == 2:
        pixels = pixels[:, :, None]
    if pixels.shape[2] == 1:
        pixels = np.repeat(pixels, 3, axis=2)
    return pixels[:, :, :3]


def display(rgb, white):
    return np.clip(rgb / max(white, 1e-30), 0.0, 1.0) ** (1.0 / 2.2)


def relative_error(estimate, reference):
    floor = 0.01 * float(np.mean(reference))
    return np.mean(np.abs(estimate - reference) / (reference + floor + 1e-30), axis=2)


def dominant_z(z):
    index = np.argmax(np.abs(z), axis=2)
    return np.take_along_axis(z, index[:, :, None], axis=2)[:, :, 0]


def _blank(ax, text):
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=7, transform=ax.transAxes)
    ax.set_axis_off()


def _show(ax, image, title, **kwargs):
    shown = ax.imshow(image, interpolation="nearest", **kwargs)
    ax.set_title(title, fontsize=7)
    ax.set_xticks([])
    ax.set_yticks([])
    return shown


def scene_figure(scene, runs, report_dir, path):
    """One row per run of `scene`; returns the path, or None when no run names an image."""
    runs = [r for r in runs if field(r, "image", "files", "mean")]
    if not runs:
        return None
    if oiio is None:
        fig, axes = new_figure(1, width=6, height=1.2)
        _blank(axes[0][0], "python3-openimageio is not installed: no scene images")
        return save(fig, path)
    fig, axes = new_figure(4, rows=len(runs), width=2.6, height=2.5)
    for row, (run, name) in enumerate(zip(runs, labels(runs))):
        files = run["image"]["files"]
        load = {k: read_exr(os.path.join(report_dir, files[k])) if files.get(k) else None
                for k in ("mean", "reference", "zmap")}
        estimate, reference = load["mean"], load["reference"]
        white = float(np.percentile(reference if reference is not None else estimate, 99))
        ref_ax, est_ax, err_ax, z_ax = axes[row]
        if reference is not None:
            _show(ref_ax, display(reference, white), f"reference ({run['image'].get('reference')})")
        else:
            _blank(ref_ax, "no reference")
        rel = number(run["image"].get("rel_mse"))
        title = f"{name}" + (f"  rel MSE {rel:.3g}" if rel is not None else "")
        if estimate is not None:
            _show(est_ax, display(estimate, white), title)
        else:
            _blank(est_ax, f"{files['mean']} unreadable")
        if estimate is not None and reference is not None and estimate.shape == reference.shape:
            shown = _show(err_ax, relative_error(estimate, reference), "relative error",
                          cmap="magma", vmin=0.0, vmax=1.0)
            fig.colorbar(shown, ax=err_ax, fraction=0.046, pad=0.02)
        else:
            _blank(err_ax, "no relative error without a reference")
        if load["zmap"] is not None:
            shown = _show(z_ax, dominant_z(load["zmap"]), "z-map (largest |z| of RGB)",
                          cmap="coolwarm", vmin=-4.0, vmax=4.0)
            fig.colorbar(shown, ax=z_ax, fraction=0.046, pad=0.02)
        else:
            _blank(z_ax, "no z-map")
    fig.suptitle(scene, fontsize=9)
    return save(fig, path)


def image_set_figure(report, report_dir, path):
    """`verify --images`: the set's mean, its relative standard error and its z-map against what
    it was tested with, the tiles that differ outlined in black on the z-map (the comparison's
    tiles_marked: its tiles_differing and the blocks of its coarsest differing scale, not its
    self-checks'). Returns the path, or None when the report has no
    image set."""
    sets = report.get("image_sets")
    if not isinstance(sets, dict):
        return None
    import matplotlib.patches as patches

    files = sets.get("image_files") or {}
    load = {k: read_exr(os.path.join(report_dir, files[k])) if files.get(k) else None
            for k in ("mean", "stderr", "zmap")}
    fig, axes = new_figure(3, width=3.0, height=2.9)
    mean_ax, se_ax, z_ax = axes[0]
    mean, stderr, z = load["mean"], load["stderr"], load["zmap"]
    replicates = len(sets.get("files") or [])
    if mean is not None:
        _show(mean_ax, display(mean, float(np.percentile(mean, 99))),
              f"mean of {replicates} replicates")
    else:
        _blank(mean_ax, "no mean image")
    if mean is not None and stderr is not None and mean.shape == stderr.shape:
        relative = np.mean(stderr / (np.abs(mean) + 0.01 * float(np.mean(np.abs(mean))) + 1e-30),
                           axis=2)
        shown = _show(se_ax, relative, "standard error / mean", cmap="magma", vmin=0.0,
                      vmax=max(float(np.percentile(relative, 99)), 1e-12))
        fig.colorbar(shown, ax=se_ax, fraction=0.046, pad=0.02)
    else:
        _blank(se_ax, "no standard error image")
    against = sets.get("against") or {}
    if z is not None:
        shown = _show(z_ax, dominant_z(z), f"z against {against.get('kind', '?')}; "
                      "tiles that differ outlined", cmap="coolwarm", vmin=-4.0, vmax=4.0)
        fig.colorbar(shown, ax=z_ax, fraction=0.046, pad=0.02)
        tile = sets.get("tile") or 8
        for c in report.get("comparisons") or []:
            if c.get("a") != "images":
                continue
            for x, y in tiles_marked(c):
                z_ax.add_patch(patches.Rectangle((x * tile - 0.5, y * tile - 0.5), tile, tile,
                                                 fill=False, edgecolor="black", linewidth=1.5))
    else:
        _blank(z_ax, "no z-map")
    fig.suptitle(f"{sets.get('images')}: {replicates} replicates, "
                 f"{sets.get('width')}×{sets.get('height')}", fontsize=8)
    return save(fig, path)
