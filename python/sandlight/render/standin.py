"""Lambertian BRDF tables from the transport engine: the ``brdf = "standin"`` option of scene files.

The shipped scenes shade with the paper's model, the spatial × spectral predictor of §3.3
(``brdf = "appearance"``: `sandlight.SandAppearance`, tabulated by `BrdfTable.from_appearance`).
This module provides the simpler alternative they used before that model existed, kept for
comparisons: for each level of the varied parameter a *Lambertian* BRDF f = R(λ)/π whose albedo
R(λ) is the sample's directional-hemispherical reflectance at normal incidence computed by this
project's Monte Carlo engine (:func:`sandlight.reflectance`, the SPLITS-style model of issue 2).
Its colour and its darkening with water are the engine's; sand's angular shape (backscatter, the
mirror reflection of wet sand at grazing angles) is missing.

The spectra of the shipped scenes are precomputed in ``sandlight/data/scenes/standin-reflectance.csv``
(regenerate with ``python -m sandlight.render.standin``); any other sample or level is computed
on the fly with the engine (about a second per level at 16 bands and 5000 rays).
"""

from __future__ import annotations

import csv
import io
import sys
from importlib import resources
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ModelFileError, ParameterError
from sandlight.render.tables import BrdfTable

if TYPE_CHECKING:
    import os

    from sandlight.sample import SandSample

__all__ = ["standin_table", "standin_reflectance", "SHIPPED", "STANDIN_CSV"]

STANDIN_CSV = "standin-reflectance.csv"
#: (preset, varied parameter, level values) precomputed for the shipped scenes.
SHIPPED = (
    ("yellow-dune", "saturation", (0.0,)),
    ("wet-beach", "saturation", tuple(np.round(np.linspace(0.0, 1.0, 16), 6))),
)
WAVELENGTHS_NM = np.arange(400.0, 701.0, 20.0)
SHIPPED_RAYS = 20000
SHIPPED_SEED = 2024


def _read_csv() -> dict[tuple[str, str, float], np.ndarray]:
    try:
        text = (resources.files("sandlight") / "data" / "scenes" / STANDIN_CSV).read_text(encoding="utf-8")
    except FileNotFoundError:
        return {}
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith("#")]
    header, body = rows[0], rows[1:]
    wl = np.array([float(h.removesuffix("nm")) for h in header[3:]])
    if not np.allclose(wl, WAVELENGTHS_NM):
        raise ModelFileError(f"{STANDIN_CSV}: wavelengths {wl.tolist()} differ from {WAVELENGTHS_NM.tolist()}")
    return {(r[0], r[1], round(float(r[2]), 6)): np.array([float(v) for v in r[3:]]) for r in body}


def standin_reflectance(
    sample: SandSample,
    preset: str | None,
    vary: str | None,
    level_values: ArrayLike,
    wavelength_nm: ArrayLike,
    *,
    rays: int = 5000,
    seed: int = SHIPPED_SEED,
    progress: bool = False,
) -> np.ndarray:
    """Normal-incidence reflectance (n_levels, n_wavelengths) of ``sample`` with ``vary`` set to
    each level value: from the shipped CSV when it holds exactly this preset, parameter, levels
    and wavelengths, else computed with the engine (common random numbers across levels)."""
    from sandlight.engine import reflectance

    levels = np.atleast_1d(np.asarray(level_values, dtype=float))
    wl = np.asarray(wavelength_nm, dtype=float)
    if preset is not None and wl.shape == WAVELENGTHS_NM.shape and np.allclose(wl, WAVELENGTHS_NM):
        from sandlight.sample import SandSample

        table = _read_csv()
        keys = [(preset, vary or "saturation", round(float(v), 6)) for v in levels]
        if sample == SandSample.preset(preset) and vary is not None and all(k in table for k in keys):
            return np.array([table[k] for k in keys])
        if vary is None and sample == SandSample.preset(preset):
            key = (preset, "saturation", round(float(sample.saturation), 6))
            if key in table:
                return table[key][None, :]
    out = []
    for v in levels:
        s = sample if vary is None else sample.replace(**{vary: float(v)})
        out.append(reflectance(s, wl, rays=rays, seed=seed, progress=progress).values)
    return np.array(out)


def standin_table(
    sample: SandSample,
    wavelength_nm: ArrayLike,
    *,
    preset: str | None = None,
    vary: str | None = None,
    level_values: ArrayLike = (0.0,),
    rays: int = 5000,
    progress: bool = False,
) -> BrdfTable:
    """The STAND-IN Lambertian table (module docstring): f = R(λ)/π per level."""
    levels = np.atleast_1d(np.asarray(level_values, dtype=float))
    if vary is None and levels.size != 1:
        raise ParameterError("levels", levels.tolist(), "a single level when no parameter varies")
    r = standin_reflectance(sample, preset, vary, levels, wavelength_nm, rays=rays, progress=progress)
    return BrdfTable.lambertian(
        np.clip(r, 0.0, 1.0),
        wavelength_nm,
        level_values=levels if vary else [0.0],
        level_name=vary or "level",
        source="STAND-IN: Lambertian f = R/pi, R from sandlight.reflectance at normal "
        "incidence (replace by SandAppearance.to_table, issue 6)",
    )


def generate(path: str | os.PathLike | None = None) -> str:
    """Recompute the shipped spectra (SHIPPED_RAYS rays per band and level) and return the CSV
    text; written to ``path`` (atomically) when given."""
    from sandlight.engine import reflectance
    from sandlight.sample import SandSample

    lines = [
        "# STAND-IN reflectance spectra for the shipped render scenes (sandlight.render.standin).",
        "# Directional-hemispherical reflectance at normal incidence, fraction, computed by",
        f"# sandlight.reflectance (this project's Monte Carlo engine) with {SHIPPED_RAYS} rays per band and",
        f"# level, seed {SHIPPED_SEED} (common random numbers across levels); standard error <= 0.0036.",
        "# Regenerate: python -m sandlight.render.standin. Source: computed by sandlight; licence: MIT",
        "# (the project's). To be replaced by the BRDF of issue 6 (SandAppearance.to_table).",
        "preset,parameter,value," + ",".join(f"{w:g}nm" for w in WAVELENGTHS_NM),
    ]
    for preset, vary, values in SHIPPED:
        base = SandSample.preset(preset)
        for v in values:
            r = reflectance(
                base.replace(**{vary: float(v)}), WAVELENGTHS_NM, rays=SHIPPED_RAYS, seed=SHIPPED_SEED, progress=False
            ).values
            lines.append(f"{preset},{vary},{v:g}," + ",".join(f"{x:.5f}" for x in r))
            print(f"{preset} {vary}={v:g}: " + " ".join(f"{x:.3f}" for x in r), file=sys.stderr)
    text = "\n".join(lines) + "\n"
    if path is not None:
        from sandlight.io import write_atomically

        write_atomically(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))
    return text


if __name__ == "__main__":
    from pathlib import Path

    target = Path(__file__).resolve().parent.parent / "data" / "scenes" / STANDIN_CSV
    generate(target)
    print(f"wrote {target}", file=sys.stderr)
