"""The forward model of the calibration: an end-member powder's reflectance for a trial k.

Public objects
--------------
EnginePowder
    sandlight's engine for a dry powder of the end-member's mineral, with k set to a trial value
    at every wavelength and n from the shipped table.
with_trial_k
    The shipped optical constants with one material's k set to one value at every wavelength.

A forward model (:class:`ForwardModel`) is any object with

* ``settings(member, wavelengths_nm) -> dict``: JSON-serialisable values that identify what it
  computes (a cached table is reused only when they are equal), and
* ``reflectance(member, wavelengths_nm, k) -> (values, stderr)``: the reflectance at normal
  incidence with the mineral's k equal to ``k`` at every wavelength, and its standard error.

Model (docs/optical-constants.md, "Calibration on pure end-members"): the USGS AREF spectra are
directional-hemispherical reflectance at (near-)normal incidence, which is what
:func:`sandlight.validation.powder_reflectance` computes (here the engine on a
:class:`sandlight.physics.powder.Powder` whose optical constants carry the trial k): one
population of spheres of the pure mineral, equal mass per log-size interval over the
end-member's ``size_um``, on-the-fly geometric optics, with independent exponential free paths
(the classic model, ``memory="none"``: the shipped calibration) or a path memory (``memory``).
Its porosity only scales the free paths of the classic model, so it does not change its
reflectance; it is recorded.
"""

from __future__ import annotations

import hashlib
import math
import zlib
from typing import TYPE_CHECKING, Protocol

import numpy as np
from numpy.typing import ArrayLike

from sandlight.checks import check_choice, check_real
from sandlight.errors import ParameterError
from sandlight.physics.media import MEMORIES
from sandlight.physics.medium import OpticalConstants

if TYPE_CHECKING:
    from sandlight.calibration.end_members import EndMember

__all__ = ["EnginePowder", "ForwardModel", "with_trial_k"]


class ForwardModel(Protocol):
    """The interface of a forward model (module docstring); :class:`EnginePowder` implements it."""

    def settings(self, member: EndMember, wavelengths_nm: ArrayLike) -> dict:
        """JSON-serialisable values that identify what the model computes."""
        ...

    def reflectance(self, member: EndMember, wavelengths_nm: ArrayLike, k: float) -> tuple[np.ndarray, np.ndarray]:
        """Reflectance at normal incidence with k = ``k`` everywhere, and its standard error."""
        ...


def with_trial_k(material: str, k: float) -> OpticalConstants:
    """The shipped optical constants with ``material``'s k replaced by ``k`` (n unchanged)."""
    from sandlight.optics import complex_index

    def index(name: str, wavelength_nm: float) -> complex:
        m = complex(complex_index(name, wavelength_nm))
        return complex(m.real, k) if name == material else m

    return index


class EnginePowder:
    """sandlight's engine for a pure powder with a trial k.

    Parameters
    ----------
    rays : int
        Rays per wavelength and trial k (≥ 1). The standard error of one value is
        √(ρ(1 − ρ)/rays).
    seed : int
        Master seed in [0, 2**32). One end-member's runs all use the seed :meth:`member_seed`,
        the same for every k and every wavelength (common random numbers): its tabulated ρ(k)
        is then a smooth function of k, whose noise is shared by neighbouring k. Different
        end-members get different seeds, so their Monte Carlo errors are independent (with one
        seed for all they are correlated, and σ of k combined over end-members, which assumes
        independence, came out 2-3 times too small in a round trip with the fake engine).
    porosity : float
        Pore volume fraction in (0, 1) (only the free-path scale; recorded).
    aspect_ratio : float
        Prolate spheroid aspect ratio in [1, 20]; 1 (spheres) by default, as no end-member
        description gives a shape the model could use.
    memory : {'none', 'channel', 'cut', 'packed'}
        Path memory of the engine (:class:`~sandlight.physics.powder.Powder`); 'none', the
        classic model of the shipped calibration, by default. Recorded in the settings only when
        not 'none', so the tables cached before the option existed stay valid.
    scattering_per_mm : float
        Scattering coefficient (mm⁻¹, ≥ 0) of inclusions and internal fractures inside the
        grains (:class:`~sandlight.physics.powder.Powder`); 0 (clear grains) by default.
        Recorded in the settings only when not 0, for the same reason.
    """

    def __init__(
        self,
        rays: int = 2000,
        seed: int = 0,
        porosity: float = 0.45,
        aspect_ratio: float = 1.0,
        memory: str = "none",
        scattering_per_mm: float = 0.0,
    ):
        self.rays = rays
        self.seed = seed
        self.porosity = porosity
        self.aspect_ratio = aspect_ratio
        self.memory = check_choice("memory", memory, MEMORIES)
        self.scattering_per_mm = check_real("scattering_per_mm", scattering_per_mm, 0.0)

    def member_seed(self, member: EndMember) -> int:
        """The engine seed of ``member``'s runs: the master seed and a CRC-32 of its id."""
        return (int(self.seed) << 32) | zlib.crc32(member.id.encode())

    def settings(self, member: EndMember, wavelengths_nm: ArrayLike) -> dict:
        """What identifies a table: the engine, its inputs and the n(λ) it will use."""
        import sandlight
        from sandlight.optics import complex_index

        n = np.real(complex_index(member.mineral, np.asarray(wavelengths_nm, dtype=float)))
        return (
            {
                "model": "sandlight.validation.powder_reflectance",
                "sandlight_version": sandlight.__version__,
                "rays": int(self.rays),
                "seed": self.member_seed(member),
                "porosity": float(self.porosity),
                "aspect_ratio": float(self.aspect_ratio),
                "n_sha256": hashlib.sha256(np.ascontiguousarray(n, dtype="<f8").tobytes()).hexdigest(),
            }
            | ({"memory": self.memory} if self.memory != "none" else {})
            | ({"scattering_per_mm": self.scattering_per_mm} if self.scattering_per_mm > 0 else {})
        )

    def reflectance(self, member: EndMember, wavelengths_nm: ArrayLike, k: float) -> tuple[np.ndarray, np.ndarray]:
        """Reflectance and its standard error of ``member``'s powder with k = ``k`` everywhere.

        Parameters
        ----------
        member : sandlight.calibration.EndMember
        wavelengths_nm : array_like
            Vacuum wavelengths in [350, 2500] nm.
        k : float
            Trial imaginary part of the refractive index, finite and > 0.
        """
        from sandlight.engine import reflectance
        from sandlight.physics.powder import Powder

        if not (isinstance(k, (int, float, np.floating)) and math.isfinite(k) and k > 0):
            raise ParameterError("k", k, "a finite number > 0")
        powder = Powder(
            member.mineral,
            member.size_um,
            self.porosity,
            self.aspect_ratio,
            with_trial_k(member.mineral, float(k)),
            memory=self.memory,
            scattering_per_mm=self.scattering_per_mm,
        )
        # share=False: every wavelength keeps its own random numbers, so the committed tables are
        # reproduced byte for byte by the calibration (spectral sharing would draw other paths).
        result = reflectance(
            powder, wavelengths_nm, rays=self.rays, seed=self.member_seed(member), progress=False, share=False
        )
        return np.asarray(result.values, dtype=float), np.asarray(result.stderr, dtype=float)
