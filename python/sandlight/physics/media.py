"""The media the engine traces (:class:`~sandlight.physics.medium.Traceable`), and how a sample
becomes one.

:func:`as_traceable` is the one resolution path of :func:`sandlight.reflectance`,
:func:`sandlight.brdf` and :func:`sandlight.fixed_incidence`: a :class:`~sandlight.SandSample`
(or a preset name) becomes a :class:`SandMedium` (the on-the-fly engine with a path memory,
docs/geometry.md) or a :class:`PackedSand` (rays traced through a stored random dense packing of
the sample's own grains, the slow reference); a Traceable is traced as it is.

Public objects
--------------
SandMedium
    A composition traced by the on-the-fly engine, with a path memory.
PackedSand
    A composition traced through an explicit packing of its grains.
IsotropicScatterers, LambertianSurface
    Reference media with known answers (Chandrasekhar's half-space, the ideal diffuse reflector).
as_traceable
    A SandSample, preset name or Traceable, with the engine's geometry and memory, as a Traceable.
engine_settings, with_engine
    A description split into the sample part and the engine's geometry and memory, and joined.
GEOMETRIES, MEMORIES, DEFAULT_MEMORY, WET_TOP_LAYER
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

from sandlight import _native
from sandlight.checks import check_choice
from sandlight.errors import ParameterError
from sandlight.physics.composition import DEFAULT_FILMS, FILM_MODELS, Composition, compose
from sandlight.physics.fine_particles import DEFAULT_PARTICLE_OPTICS, PARTICLE_OPTICS
from sandlight.physics.medium import COATING_OPTICS, OpticalConstants, Traceable, mie_majorants, native_medium
from sandlight.physics.pigment import PIGMENT_DIAMETER_UM

if TYPE_CHECKING:
    from sandlight.sample import SandSample

__all__ = [
    "GEOMETRIES",
    "MEMORIES",
    "DEFAULT_MEMORY",
    "WET_TOP_LAYER",
    "SandMedium",
    "PackedSand",
    "IsotropicScatterers",
    "LambertianSurface",
    "as_traceable",
    "engine_settings",
    "with_engine",
]

GEOMETRIES = ("on-the-fly", "explicit")
MEMORIES = ("none", "channel", "cut", "packed")
#: Path memory of the on-the-fly engine when none is asked for (docs/geometry.md): 'packed', the
#: closest to the explicit reference, dry and wet (issue 17 §4, docs/wet-sand.md).
DEFAULT_MEMORY = "packed"

#: Why the surface-layer models other than the default are not validated for wet sand
#: (docs/geometry.md, "Wet sand"). 'packed', the default, is compared with the measured wet/dry
#: pair (docs/wet-sand.md), where it agrees far better than the classic model; no warning for it.
WET_TOP_LAYER = (
    "memory='cut' and geometry='explicit' put the flat water surface of a water-filled surface pore at "
    "the top of the surface layer, above the highest grain, so with water-filled pores (saturation above "
    "film_saturation) they lose more light in the water bands than the classic model; unlike the default "
    "memory='packed' they were not compared with the measured wet/dry pair (docs/wet-sand.md, "
    "docs/geometry.md 'Wet sand')"
)


def with_engine(description: Mapping, geometry: str, memory: str) -> dict:
    """``description`` with the engine's ``geometry`` and ``memory``, recorded only when not
    'on-the-fly' and 'none', so that descriptions (and the checkpoint keys and BRDF files made
    from them) read as they did before either existed."""
    if geometry == "on-the-fly" and memory == "none":
        return dict(description)
    return {**description, "geometry": geometry, "memory": memory}


def engine_settings(description: Mapping) -> tuple[dict, str, str]:
    """``(rest, geometry, memory)`` of a :meth:`Traceable.describe` dict: the engine's geometry
    and path memory ('on-the-fly' and 'none' when absent, as :func:`with_engine` writes them) and
    everything else."""
    rest = {k: v for k, v in description.items() if k not in ("geometry", "memory")}
    return rest, description.get("geometry", "on-the-fly"), description.get("memory", "none")


@dataclass(frozen=True)
class SandMedium:
    """A composition traced by the on-the-fly engine (each next particle drawn at random).

    Parameters
    ----------
    composition : Composition
        The particle populations and pore space (:func:`sandlight.physics.composition.compose`).
    memory : {'none', 'channel', 'cut', 'packed'}
        Near-surface path memory (docs/geometry.md); 'none' is the classic model.
    description : mapping
        What the composition is, recorded in results (a sample's ``to_dict()``).
    optical_constants : callable, optional
        ``(material, wavelength_nm) -> n + ik`` replacing the shipped tables (what-if runs).
    coating_optics : {'uniform', 'mie'}
        How a coating's iron oxide acts (:data:`~sandlight.physics.medium.COATING_OPTICS`):
        'uniform' (an absorbing slab, the default: 'mie' costs about 3x the time and changed the
        presets' chroma little, docs/optical-constants.md) or 'mie' (scattering pigment
        crystals, docs/model.md §2.4).
    pigment_diameter_um : float
        Diameter (µm) of the pigment crystals for 'mie'.
    films : {'uniform', 'pendular'}
        Where the composition's film water sits (:data:`~sandlight.physics.composition.FILM_MODELS`;
        recorded here, applied by :func:`~sandlight.physics.composition.compose`): 'pendular'
        (rings at the grain contacts, docs/model.md §2.5; the default,
        :data:`~sandlight.physics.composition.DEFAULT_FILMS`) or 'uniform' (a film on every particle).
    particle_optics : {'geometric', 'mie'}
        How the separate iron-oxide particles of the ``particles`` form are traced
        (:data:`~sandlight.physics.fine_particles.PARTICLE_OPTICS`): 'geometric' (spheres in
        geometric optics, the default: the engine the predictor bank was trained on) or 'mie'
        (Lorenz–Mie volume scatterers in the pore space, docs/model.md §2.4 item 8; with the
        memories 'none' and 'packed' only). No effect on samples of the other forms.
    """

    composition: Composition
    memory: str = DEFAULT_MEMORY
    description: Mapping = field(default_factory=dict)
    optical_constants: OpticalConstants | None = None
    coating_optics: str = "uniform"
    pigment_diameter_um: float = PIGMENT_DIAMETER_UM
    films: str = DEFAULT_FILMS
    particle_optics: str = DEFAULT_PARTICLE_OPTICS

    def __post_init__(self) -> None:
        check_choice("memory", self.memory, MEMORIES)
        check_choice("coating_optics", self.coating_optics, COATING_OPTICS)
        check_choice("films", self.films, FILM_MODELS)
        check_choice("particle_optics", self.particle_optics, PARTICLE_OPTICS)
        if self.particle_optics == "mie" and self.memory not in ("none", "packed"):
            raise ParameterError("memory", self.memory, "'none' or 'packed' with particle_optics='mie'")

    @classmethod
    def from_sample(
        cls,
        sample: SandSample,
        memory: str | None = None,
        *,
        optical_constants: OpticalConstants | None = None,
        coating_optics: str = "uniform",
        pigment_diameter_um: float = PIGMENT_DIAMETER_UM,
        films: str = DEFAULT_FILMS,
        particle_optics: str = DEFAULT_PARTICLE_OPTICS,
    ) -> SandMedium:
        """The medium of a :class:`~sandlight.SandSample` (``memory`` None: :data:`DEFAULT_MEMORY`)."""
        memory = DEFAULT_MEMORY if memory is None else memory
        return cls(
            compose(sample, films),
            memory,
            sample.to_dict(),
            optical_constants,
            coating_optics,
            pigment_diameter_um,
            films,
            particle_optics,
        )

    @cached_property
    def majorants(self) -> tuple[float | None, ...] | None:
        """The Mie majorants of the populations with ``particle_optics='mie'`` (computed once;
        :func:`~sandlight.physics.medium.mie_majorants`), None otherwise."""
        if self.particle_optics != "mie":
            return None
        return mie_majorants(self.composition, self.optical_constants)

    def medium(self, wavelength_nm: float) -> _native.Medium:
        """The native medium at ``wavelength_nm`` (nm)."""
        return native_medium(
            self.composition,
            wavelength_nm,
            memory=self.memory,
            optical_constants=self.optical_constants,
            coating_optics=self.coating_optics,
            pigment_diameter_um=self.pigment_diameter_um,
            particle_optics=self.particle_optics,
            majorants=self.majorants,
        )

    def describe(self) -> dict:
        """The description, with geometry and memory when the memory is not 'none', the coating
        optics when not 'uniform', the films when not 'uniform' (the film model before issue 17)
        and the particle optics when not 'geometric'."""
        out = with_engine(self.description, "on-the-fly", self.memory)
        if self.coating_optics != "uniform":
            out |= {"coating_optics": self.coating_optics, "pigment_diameter_um": self.pigment_diameter_um}
        if self.films != "uniform":
            out |= {"films": self.films}
        if self.particle_optics != DEFAULT_PARTICLE_OPTICS:
            out |= {"particle_optics": self.particle_optics}
        return out


@dataclass(frozen=True)
class PackedSand:
    """A composition traced through an explicit packing of its grains (the slow reference).

    Rays follow the same per-particle physics through a stored random dense packing
    (:func:`sandlight.physics.packing.generate_packing`, wavelength independent), down to the
    composition's depth (docs/geometry.md). ``optical_constants`` as in :class:`SandMedium`.
    The media of all wavelengths share the packing, so their paths can be shared
    (docs/transport.md, "Spectral path sharing").
    """

    composition: Composition
    packing: _native.Packing
    description: Mapping = field(default_factory=dict)
    optical_constants: OpticalConstants | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.packing, _native.Packing):
            raise ParameterError("packing", self.packing, "None or a sandlight._native.Packing (generate_packing)")

    @classmethod
    def generate(cls, composition: Composition, *, seed: int = 0, description: Mapping | None = None) -> PackedSand:
        """Packs the composition's grains (default box, ``seed``) and traces through them."""
        from sandlight.physics.packing import generate_packing, reference_grain_mm

        packing = generate_packing(
            native_medium(composition, 550.0), reference_mm=reference_grain_mm(composition), seed=seed
        )
        return cls(composition, packing, {} if description is None else description)

    def medium(self, wavelength_nm: float) -> _native.Medium:
        """The native explicit medium at ``wavelength_nm`` (nm)."""
        medium = native_medium(self.composition, wavelength_nm, optical_constants=self.optical_constants)
        return medium.explicit(self.packing, self.composition.depth_mm)

    def describe(self) -> dict:
        """The description, with geometry 'explicit' and memory 'none'."""
        return with_engine(self.description, "explicit", "none")


@dataclass(frozen=True)
class IsotropicScatterers:
    """Reference medium: isotropic point scatterers of albedo ω (Chandrasekhar's half-space).

    Free paths are exponential with unit mean; ``depth`` is the optical thickness of the slab
    (mean free paths, ``inf`` for a half-space). The wavelength plays no part.
    """

    albedo: float
    depth: float = math.inf

    def medium(self, wavelength_nm: float) -> _native.Medium:
        """The native medium (the same at every wavelength)."""
        return _native.Medium.isotropic(float(self.albedo), float(self.depth))

    def describe(self) -> dict:
        """``{"reference": "isotropic scatterers", "albedo": ω}``, and the depth when finite."""
        out: dict[str, Any] = {"reference": "isotropic scatterers", "albedo": float(self.albedo)}
        if math.isfinite(self.depth):
            out["depth"] = float(self.depth)
        return out


@dataclass(frozen=True)
class LambertianSurface:
    """Reference surface: ideal diffuse reflector of albedo a, f = a/π (the wavelength plays no part)."""

    albedo: float

    def medium(self, wavelength_nm: float) -> _native.Medium:
        """The native surface (the same at every wavelength)."""
        return _native.Medium.lambertian(float(self.albedo))

    def describe(self) -> dict:
        """``{"reference": "lambertian surface", "albedo": a}``."""
        return {"reference": "lambertian surface", "albedo": float(self.albedo)}


def as_traceable(
    sample: SandSample | str | Traceable,
    *,
    geometry: str = "on-the-fly",
    memory: str | None = None,
    packing: _native.Packing | None = None,
    seed: int = 0,
) -> Traceable:
    """What the engine traces for ``sample``.

    Parameters
    ----------
    sample : SandSample, str or Traceable
        A sample, the name of a preset (``SandSample.preset``), or a Traceable medium, which is
        returned as it is (it carries its own geometry and memory).
    geometry : {'on-the-fly', 'explicit'}
        'on-the-fly' gives a :class:`SandMedium`; 'explicit' a :class:`PackedSand` through
        ``packing``, or through a packing generated from ``seed`` when None.
    memory : {'none', 'channel', 'cut', 'packed'}, optional
        Path memory of the on-the-fly engine (default :data:`DEFAULT_MEMORY`); 'none' (or None)
        with explicit geometry.

    Warns
    -----
    UserWarning
        :data:`WET_TOP_LAYER`, for memory 'cut' or explicit geometry on a sample with water-filled pores.
    """
    from sandlight.sample import SandSample

    if isinstance(sample, Traceable):
        if geometry != "on-the-fly" or memory not in (None, "none") or packing is not None:
            raise ParameterError(
                "geometry",
                geometry,
                "'on-the-fly' (with no memory or packing) for a Traceable medium such as a reference medium "
                "or a Powder, which carries its own",
            )
        return sample
    if isinstance(sample, str):
        sample = SandSample.preset(sample)
    if not isinstance(sample, SandSample):
        raise ParameterError(
            "sample", sample, "a SandSample, the name of a preset or a Traceable medium (sandlight.physics.media)"
        )
    comp = compose(sample)
    geometry = check_choice("geometry", geometry, GEOMETRIES)
    if memory is None:  # the explicit packing is its own path memory
        memory = DEFAULT_MEMORY if geometry == "on-the-fly" else "none"
    memory = check_choice("memory", memory, MEMORIES)
    if comp.water_filled_probability > 0 and (memory == "cut" or geometry == "explicit"):
        warnings.warn(WET_TOP_LAYER, UserWarning, stacklevel=3)
    if geometry == "on-the-fly":
        return SandMedium(comp, memory, sample.to_dict())
    if memory != "none":
        raise ParameterError("memory", memory, "'none' with geometry='explicit' (memory models the on-the-fly engine)")
    if packing is None:
        return PackedSand.generate(comp, seed=seed, description=sample.to_dict())
    return PackedSand(comp, packing, sample.to_dict())
