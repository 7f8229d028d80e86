"""Plots of spectra (matplotlib, headless)."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike


def plot_spectrum(
    wavelengths_nm: ArrayLike,
    values: ArrayLike,
    stderr: ArrayLike,
    path: str | os.PathLike,
    *,
    title: str | None = None,
    label: str = "sandlight (Monte Carlo)",
    others: Sequence[tuple[ArrayLike, ArrayLike, str]] = (),
) -> None:
    """Reflectance vs wavelength with a ±2 standard-error band, to a PNG written atomically.

    ``others`` is a sequence of (wavelengths_nm, values, label) curves drawn for comparison.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sandlight.io import atomic_path

    wl = np.asarray(wavelengths_nm, dtype=float)
    v = np.asarray(values, dtype=float)
    e = np.asarray(stderr, dtype=float)
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    ax.plot(wl, v, "-o" if wl.size < 40 else "-", ms=3, label=label, color="C3")
    ax.fill_between(wl, v - 2 * e, v + 2 * e, color="C3", alpha=0.25, lw=0, label="±2 standard errors")
    for w2, v2, lab in others:
        ax.plot(w2, v2, "-", lw=1, label=lab)
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("directional-hemispherical reflectance")
    top = max([float(np.nanmax(v + 2 * e))] + [float(np.nanmax(np.asarray(v2, dtype=float))) for _, v2, _ in others])
    ax.set_ylim(0, max(1e-3, top * 1.1))
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
