"""A dry powder of one pure material, as a medium the engine traces.

A :class:`~sandlight.SandSample` is a quartz sand with at most 10 wt% iron oxide, so it cannot
describe an iron-oxide end-member (the pure hematite of the paper's Figure 3). :class:`Powder`
builds the same kind of medium directly: one particle population of the material, exponential
free paths with the mean ℓ = 4φ / [(1 − φ) ⟨S⟩/⟨V⟩] (docs/model.md §2.1), particles drawn on
the fly with the classic model or a path memory (``memory``, as a sand's), no water, infinitely
deep. Trace it like a sample:
``sandlight.reflectance(Powder("hematite", 2.5), wavelengths_nm, rays=...)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from sandlight import _native
from sandlight.checks import check_choice, check_real
from sandlight.errors import ParameterError
from sandlight.optics import MATERIALS
from sandlight.physics.composition import Composition, mean_free_path_mm, population
from sandlight.physics.media import MEMORIES, with_engine
from sandlight.physics.medium import OpticalConstants, native_medium
from sandlight.physics.sizes import SizeDistribution

__all__ = ["Powder"]


@dataclass(frozen=True)
class Powder:
    """A dry powder of one pure material (a :class:`~sandlight.physics.medium.Traceable`).

    Parameters
    ----------
    material : str
        A name of :data:`sandlight.optics.MATERIALS`.
    diameter_um : float or (float, float)
        Volume-equivalent particle diameter in µm (all equal), or a sieve fraction
        (d_min, d_max) in µm, taken as equal mass per logarithmic size interval.
    porosity : float
        Pore volume fraction φ in (0, 1); only the free-path scale depends on it.
    aspect_ratio : float
        Prolate spheroid aspect ratio ε in [1, 20].
    optical_constants : callable, optional
        (material, λ in nm) → n + ik in place of the shipped tables (the calibration's trial k).
    memory : {'none', 'channel', 'cut', 'packed'}
        Near-surface path memory of the on-the-fly engine (docs/geometry.md). 'none', the classic
        model, by default: the powders of the shipped calibration were traced with it
        (docs/optical-constants.md); a sand's default is 'packed'.
    scattering_per_mm : float
        Scattering coefficient σ (mm⁻¹, ≥ 0) of the inclusions and internal fractures of the
        grains, isotropic and grey (as ``SandSample.host_scattering`` for the quartz host,
        docs/model.md §2.4 item 9). 0, a clear crystal, by default.
    """

    material: str
    diameter_um: float | tuple[float, float]
    porosity: float = 0.45
    aspect_ratio: float = 1.0
    optical_constants: OpticalConstants | None = None
    memory: str = "none"
    scattering_per_mm: float = 0.0

    def __post_init__(self) -> None:
        check_choice("material", self.material, MATERIALS)
        check_choice("memory", self.memory, MEMORIES)
        allowed = "a diameter > 0 µm, or (d_min, d_max) with 0 < d_min < d_max"
        try:
            sizes = self.sizes_um
        except (TypeError, ValueError):
            raise ParameterError("diameter_um", self.diameter_um, allowed) from None
        if (
            sizes.size not in (1, 2)
            or not np.all(np.isfinite(sizes))
            or np.any(sizes <= 0)
            or (sizes.size == 2 and sizes[1] <= sizes[0])
        ):
            raise ParameterError("diameter_um", self.diameter_um, allowed)
        check_real("porosity", self.porosity, 0.0, 1.0, low_open=True, high_open=True)
        check_real("aspect_ratio", self.aspect_ratio, 1.0, 20.0)
        check_real("scattering_per_mm", self.scattering_per_mm, 0.0)

    @property
    def sizes_um(self) -> np.ndarray:
        """The diameter, or the sieve fraction's limits, in µm (1 or 2 values)."""
        return np.atleast_1d(np.asarray(self.diameter_um, dtype=float))

    @cached_property
    def composition(self) -> Composition:
        """The powder's one population and pore space (no water, infinitely deep)."""
        d_mm = self.sizes_um * 1e-3
        if d_mm.size == 1:
            sizes = SizeDistribution("lognormal", d_mm[0], d_mm[0], median_mm=d_mm[0], spread=1.0)
        else:
            sizes = SizeDistribution("loguniform", d_mm[0], d_mm[1])
        pops = (
            population(
                f"{self.material} powder",
                1.0,
                sizes,
                self.aspect_ratio,
                {self.material: 1.0},
                core_scattering_per_mm=self.scattering_per_mm,
            ),
        )
        return Composition(
            populations=pops,
            porosity=self.porosity,
            mean_free_path_mm=mean_free_path_mm(pops, self.porosity),
            film_thickness_mm=0.0,
            water_filled_probability=0.0,
            depth_mm=math.inf,
        )

    def medium(self, wavelength_nm: float) -> _native.Medium:
        """The native medium at ``wavelength_nm`` (nm)."""
        return native_medium(
            self.composition, wavelength_nm, memory=self.memory, optical_constants=self.optical_constants
        )

    def describe(self) -> dict:
        """``{"material", "diameter_um" (list, µm), "porosity", "aspect_ratio"}``, with
        ``scattering_per_mm`` when not 0, and geometry and memory when the memory is not 'none'."""
        own = {
            "material": self.material,
            "diameter_um": self.sizes_um.tolist(),
            "porosity": self.porosity,
            "aspect_ratio": self.aspect_ratio,
        } | ({"scattering_per_mm": self.scattering_per_mm} if self.scattering_per_mm > 0 else {})
        return with_engine(own, "on-the-fly", self.memory)
