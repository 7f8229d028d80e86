"""The BRDF of a sample at one incidence and wavelength, as the page draws it.

f(ω_i, ω_o, λ) in sr⁻¹ comes from `sandlight.appearance.SandAppearance` (spectral × spatial
predictor, paper §3.3). The light comes from zenith angle θ_i in the plane φ = 0
(ω_i = (sin θ_i, 0, cos θ_i), pointing towards the light); the viewer's direction is
ω_o = (sin θ_o cos φ_o, sin θ_o sin φ_o, cos θ_o).

- The **polar map** is f on a grid of θ_o (0–90°, cell centres) × φ_o (0–360°, cell centres).
- The **principal plane** is f along φ_o ∈ {0°, 180°}, written with a signed view zenith
  θ ∈ (−90°, 90°): θ > 0 on the light's side (back-scattering, φ_o = 0), θ < 0 on the mirror
  side (forward scattering, φ_o = 180°).
"""

from __future__ import annotations

import functools
import warnings
from typing import Any

import numpy as np

from sandlight.appearance import SandAppearance
from sandlight.errors import ParameterError
from sandlight.sample import SandSample

__all__ = ["appearance_of", "brdf_answer"]


@functools.lru_cache(maxsize=16)
def appearance_of(sample: SandSample) -> tuple[SandAppearance, tuple[str, ...]]:
    """The `SandAppearance` of a sample and the warnings its construction gave (e.g. the sample
    differs from the spatial mesh's base sample in a parameter the mesh does not vary); the
    last 16 are kept (samples are immutable and hashable)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        app = SandAppearance(sample)
    return app, tuple(sorted({str(w.message) for w in caught}))


def _directions(theta_deg: np.ndarray, phi_deg: np.ndarray) -> np.ndarray:
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


def brdf_answer(
    sample: SandSample, incidence_deg: float, wavelength_nm: float, n_theta: int, n_phi: int
) -> dict[str, Any]:
    """The body of ``POST /api/brdf`` (docs/explorer.md): polar map and principal plane, sr⁻¹.

    Raises
    ------
    ParameterError
        ``wavelength_nm`` outside the spectral model's range, or a sample the models do not cover.
    """
    app, notes = appearance_of(sample)
    low, high = float(app.wavelengths_nm[0]), float(app.wavelengths_nm[-1])
    if not low <= wavelength_nm <= high:
        raise ParameterError(
            "wavelength_nm", wavelength_nm, f"a wavelength in [{low:g}, {high:g}] nm (the models' range)"
        )
    wi = _directions(np.array(incidence_deg), np.array(0.0))
    theta = (np.arange(n_theta) + 0.5) * 90.0 / n_theta
    phi = (np.arange(n_phi) + 0.5) * 360.0 / n_phi
    grid_t, grid_p = np.meshgrid(theta, phi, indexing="ij")
    polar = app.brdf(wi, _directions(grid_t.ravel(), grid_p.ravel()), [wavelength_nm])[:, 0].reshape(n_theta, n_phi)
    signed = np.linspace(-89.0, 89.0, 179)
    plane = app.brdf(wi, _directions(np.abs(signed), np.where(signed >= 0, 0.0, 180.0)), [wavelength_nm])[:, 0]
    return {
        "incidence_deg": incidence_deg,
        "wavelength_nm": wavelength_nm,
        "unit": "1/sr",
        "warnings": list(notes),
        "albedo": float(app.albedo(wi, [wavelength_nm])[0, 0]),
        "polar": {"theta_deg": theta.tolist(), "phi_deg": phi.tolist(), "f": polar.tolist()},
        "principal_plane": {"theta_deg": signed.tolist(), "f": plane.tolist()},
    }
