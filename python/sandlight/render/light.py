"""The light of a render: the sky as a latitude–longitude texture and the sun as a small disc.

The Preetham sky (:class:`sandlight.sky.PreethamSky`) is evaluated once per frame on a grid of
the upper hemisphere — n_θ rows of equal zenith-angle width, n_φ columns, values at cell centres,
φ = atan2(y, x) in the frame x east, y north, z up — and handed to the renderer as a texture
(bilinear lookup) with a CDF for importance sampling. The sun is a uniform disc of the
atmosphere-attenuated solar radiance over :data:`sandlight.sky.SUN_SOLID_ANGLE_SR`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

__all__ = ["Lighting", "sky_grid_directions"]

#: Default sky texture: 1° in zenith angle, 1.4° in azimuth.
DEFAULT_SKY_RESOLUTION = (90, 256)


def sky_grid_directions(n_theta: int, n_phi: int) -> np.ndarray:
    """Unit directions (n_theta, n_phi, 3) at the cell centres of the renderer's sky grid."""
    theta = (np.arange(n_theta) + 0.5) * (0.5 * np.pi / n_theta)
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


@dataclass(frozen=True)
class Lighting:
    """Sky texture and sun of one frame.

    Attributes
    ----------
    wavelength_nm : numpy.ndarray, shape (n_bands,)
    sky_radiance : numpy.ndarray, float32, shape (n_theta, n_phi, n_bands)
        W m⁻² sr⁻¹ nm⁻¹ at the cell centres of :func:`sky_grid_directions`.
    sun_direction : numpy.ndarray, shape (3,)
        Unit vector towards the sun (x east, y north, z up).
    sun_radiance : numpy.ndarray, shape (n_bands,)
        Radiance of the solar disc, W m⁻² sr⁻¹ nm⁻¹ (zeros: no sun).
    sun_solid_angle_sr : float
    """

    wavelength_nm: np.ndarray
    sky_radiance: np.ndarray
    sun_direction: np.ndarray
    sun_radiance: np.ndarray
    sun_solid_angle_sr: float

    def __post_init__(self):
        wl = np.atleast_1d(np.asarray(self.wavelength_nm, dtype=float))
        sky = np.ascontiguousarray(self.sky_radiance, dtype=np.float32)
        if sky.ndim != 3 or sky.shape[2] != wl.size or sky.shape[0] < 2 or sky.shape[1] < 4:
            raise ParameterError(
                "sky_radiance",
                f"array of shape {np.shape(self.sky_radiance)}",
                f"shape (n_theta ≥ 2, n_phi ≥ 4, {wl.size})",
            )
        if not np.isfinite(sky).all() or (sky < 0).any():
            raise ParameterError("sky_radiance", "negative or non-finite values", "finite radiances ≥ 0")
        sun = np.asarray(self.sun_direction, dtype=float)
        if sun.shape != (3,) or not np.isfinite(sun).all() or np.linalg.norm(sun) == 0:
            raise ParameterError("sun_direction", self.sun_direction, "a finite non-zero 3-vector")
        rad = np.broadcast_to(np.asarray(self.sun_radiance, dtype=float), wl.shape).copy()
        if not np.isfinite(rad).all() or (rad < 0).any():
            raise ParameterError("sun_radiance", self.sun_radiance, "finite radiances ≥ 0")
        if not 0.0 < float(self.sun_solid_angle_sr) < 2 * np.pi:
            raise ParameterError("sun_solid_angle_sr", self.sun_solid_angle_sr, "a solid angle in (0, 2π) sr")
        object.__setattr__(self, "wavelength_nm", wl)
        object.__setattr__(self, "sky_radiance", sky)
        object.__setattr__(self, "sun_direction", sun / np.linalg.norm(sun))
        object.__setattr__(self, "sun_radiance", rad)
        object.__setattr__(self, "sun_solid_angle_sr", float(self.sun_solid_angle_sr))

    @classmethod
    def preetham(
        cls,
        turbidity: float,
        sun_direction: ArrayLike,
        wavelength_nm: ArrayLike,
        *,
        resolution: tuple[int, int] = DEFAULT_SKY_RESOLUTION,
    ) -> Lighting:
        """Preetham et al. (1999) sky and sun for a turbidity and a sun direction (above the horizon)."""
        from sandlight.sky import PreethamSky

        n_theta, n_phi = _resolution(resolution)
        sky = PreethamSky(turbidity, sun_direction)
        wl = np.atleast_1d(np.asarray(wavelength_nm, dtype=float))
        radiance = sky.radiance(sky_grid_directions(n_theta, n_phi), wl)
        return cls(wl, radiance, sky.sun_direction, sky.sun_radiance(wl), sky.sun_solid_angle)

    @classmethod
    def uniform(
        cls,
        sky_radiance: ArrayLike,
        wavelength_nm: ArrayLike,
        *,
        sun_direction: ArrayLike = (0.0, 0.0, 1.0),
        sun_irradiance: ArrayLike = 0.0,
        sun_solid_angle_sr: float | None = None,
        resolution: tuple[int, int] = (8, 16),
    ) -> Lighting:
        """A sky of the same radiance in every direction (per band), and optionally a sun of given
        normal irradiance E☉ (W m⁻² nm⁻¹), i.e. radiance E☉/Ω☉. For tests and studio lighting."""
        from sandlight.sky import SUN_SOLID_ANGLE_SR

        n_theta, n_phi = _resolution(resolution)
        wl = np.atleast_1d(np.asarray(wavelength_nm, dtype=float))
        sky = np.broadcast_to(np.asarray(sky_radiance, dtype=float), wl.shape)
        omega = SUN_SOLID_ANGLE_SR if sun_solid_angle_sr is None else float(sun_solid_angle_sr)
        sun = np.broadcast_to(np.asarray(sun_irradiance, dtype=float), wl.shape) / omega
        return cls(
            wl, np.broadcast_to(sky, (n_theta, n_phi, wl.size)), np.asarray(sun_direction, dtype=float), sun, omega
        )

    @property
    def sun_elevation_deg(self) -> float:
        return float(np.degrees(np.arcsin(np.clip(self.sun_direction[2], -1.0, 1.0))))

    def horizontal_irradiance(self) -> np.ndarray:
        """Irradiance on unobstructed horizontal ground, W m⁻² nm⁻¹ per band: the sun's
        E☉ cos θ☉ plus ∫ L_sky cos θ dω over the sky texture (midpoint rule on its cells)."""
        n_theta, n_phi = self.sky_radiance.shape[:2]
        edges = np.linspace(0.0, 0.5 * np.pi, n_theta + 1)
        # ∫ cos θ dω over a row of cells = Δφ (sin²θ1 − sin²θ0)/2 per cell.
        row_weight = (2.0 * np.pi / n_phi) * 0.5 * (np.sin(edges[1:]) ** 2 - np.sin(edges[:-1]) ** 2)
        sky = np.einsum("tpb,t->b", self.sky_radiance.astype(float), row_weight)
        sun = self.sun_radiance * self.sun_solid_angle_sr * max(self.sun_direction[2], 0.0)
        return sky + sun


def _resolution(resolution: tuple[int, int]) -> tuple[int, int]:
    try:
        n_theta, n_phi = (int(v) for v in resolution)
    except (TypeError, ValueError):
        raise ParameterError("sky_resolution", resolution, "two whole numbers (n_theta, n_phi)") from None
    if not (2 <= n_theta <= 2048 and 4 <= n_phi <= 4096):
        raise ParameterError("sky_resolution", resolution, "n_theta in [2, 2048] and n_phi in [4, 4096]")
    return n_theta, n_phi
