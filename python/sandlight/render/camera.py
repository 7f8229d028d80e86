"""Pinhole camera: position, viewing direction, horizontal field of view, resolution."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from sandlight.checks import check_whole_number
from sandlight.errors import ParameterError

__all__ = ["Camera"]

MAX_PIXELS_PER_SIDE = 16384


@dataclass(frozen=True)
class Camera:
    """A pinhole camera (x east, y north, z up; metres).

    Attributes
    ----------
    position : numpy.ndarray, shape (3,)
        Eye point, metres.
    forward : numpy.ndarray, shape (3,)
        Viewing direction (normalised here).
    fov_deg : float
        Horizontal field of view, degrees in (0, 170).
    width, height : int
        Image size in pixels.
    """

    position: np.ndarray
    forward: np.ndarray
    fov_deg: float
    width: int
    height: int

    def __post_init__(self):
        p = np.asarray(self.position, dtype=float)
        f = np.asarray(self.forward, dtype=float)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ParameterError("camera.position", self.position, "three finite coordinates in metres")
        if f.shape != (3,) or not np.isfinite(f).all() or np.linalg.norm(f) < 1e-12:
            raise ParameterError("camera.forward", self.forward, "a finite non-zero direction")
        f = f / np.linalg.norm(f)
        if np.hypot(f[0], f[1]) < 1e-6:
            raise ParameterError(
                "camera.forward",
                self.forward,
                "a direction that is not straight up or down (the image's up is taken from the vertical)",
            )
        if not (0.0 < float(self.fov_deg) < 170.0):
            raise ParameterError("camera.fov_deg", self.fov_deg, "a horizontal field of view in (0, 170) degrees")
        for name in ("width", "height"):
            check_whole_number(
                f"output.{name}", getattr(self, name), 1, MAX_PIXELS_PER_SIDE, noun="a whole number of pixels"
            )
        object.__setattr__(self, "position", p)
        object.__setattr__(self, "forward", f)

    @classmethod
    def look_at(cls, position: npt.ArrayLike, target: npt.ArrayLike, fov_deg: float, width: int, height: int) -> Camera:
        d = np.asarray(target, dtype=float) - np.asarray(position, dtype=float)
        return cls(position, d, fov_deg, width, height)

    @classmethod
    def heading(
        cls, position: npt.ArrayLike, heading_deg: float, pitch_deg: float, fov_deg: float, width: int, height: int
    ) -> Camera:
        """Looking towards ``heading_deg`` (from north, clockwise) and ``pitch_deg`` above the
        horizontal (negative: down)."""
        if not -89.0 <= pitch_deg <= 89.0:
            raise ParameterError("camera.pitch_deg", pitch_deg, "an angle in [-89, 89] degrees")
        h, p = np.radians(heading_deg), np.radians(pitch_deg)
        return cls(position, [np.sin(h) * np.cos(p), np.cos(h) * np.cos(p), np.sin(p)], fov_deg, width, height)

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(forward, right, up): right and up scaled to the half-width and half-height of the image
        plane at unit distance."""
        f = self.forward
        right = np.cross(f, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, f)
        half_w = np.tan(0.5 * np.radians(self.fov_deg))
        half_h = half_w * self.height / self.width
        return f, right * half_w, up * half_h

    def native_args(self) -> dict:
        f, r, u = self.basis()
        return {
            "camera_origin": self.position.tolist(),
            "camera_forward": f.tolist(),
            "camera_right": r.tolist(),
            "camera_up": u.tolist(),
            "width": int(self.width),
            "height": int(self.height),
        }

    def directions(self) -> np.ndarray:
        """Unit directions through pixel centres, shape (height, width, 3)."""
        f, r, u = self.basis()
        x = 2.0 * (np.arange(self.width) + 0.5) / self.width - 1.0
        y = 1.0 - 2.0 * (np.arange(self.height) + 0.5) / self.height
        d = f[None, None] + x[None, :, None] * r[None, None] + y[:, None, None] * u[None, None]
        return d / np.linalg.norm(d, axis=-1, keepdims=True)
