"""The optical medium the native engine traces, and the interface of everything traceable.

:class:`Traceable` is what :func:`sandlight.reflectance`, :func:`sandlight.brdf` and
:func:`sandlight.fixed_incidence` trace: anything that gives the native medium at a wavelength
and describes itself for the results. Its variants (a sand sample's composition, an explicit
packing, the isotropic and Lambertian references) are in :mod:`sandlight.physics.media`, the
pure-material powder in :mod:`sandlight.physics.powder`.

:func:`native_medium` builds the native particulate medium of a :class:`Composition` at one
wavelength. Mixing rules (docs/transport.md): a core or coating made of several materials gets
the volume-weighted mean of their complex indices, n̄ = Σ vⱼ nⱼ and k̄ = Σ vⱼ kⱼ, hence the
volume-weighted absorption coefficient ᾱ = Σ vⱼ αⱼ — the dilute-inclusion limit of
docs/model.md §2.4 (Maxwell Garnett is the refinement for dense inclusions). The quartz host's
k is multiplied by the composition's ``host_absorption`` first (:func:`with_host_absorption`).
With ``coating_optics='mie'`` a coating's iron oxide is instead a Mie-scattering pigment in its
kaolinite matrix (:mod:`sandlight.physics.pigment`, docs/model.md §2.4). Either coating covers the
composition's ``coating_coverage`` of its particles' surface (patches drawn per surface point by
the engine; bare surface elsewhere). With ``particle_optics='mie'`` the separate iron-oxide
particles of the ``particles`` form are Lorenz–Mie volume scatterers in the pore space
(:mod:`sandlight.physics.fine_particles`, docs/model.md §2.4 item 8).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Protocol, runtime_checkable

import numpy as np

from sandlight import _native
from sandlight.checks import check_choice
from sandlight.optics import complex_index
from sandlight.physics.composition import HOST_MATERIAL, IRON_OXIDE_PARTICLES, Composition, Population
from sandlight.physics.fine_particles import (
    DEFAULT_PARTICLE_OPTICS,
    PARTICLE_OPTICS,
    check_below_majorant,
    majorant,
    mie_optics,
    size_nodes_um,
)
from sandlight.physics.pigment import PIGMENT_DIAMETER_UM
from sandlight.physics.pigment import coating_optics as pigmented_coating
from sandlight.physics.sizes import SizeDistribution

__all__ = [
    "Traceable",
    "OpticalConstants",
    "COATING_OPTICS",
    "native_medium",
    "mie_majorants",
    "absorption_per_mm",
    "with_host_absorption",
    "shipped_index",
]

#: How a coating's iron oxide acts: 'uniform' (absorbing, non-scattering slab with the volume
#: mean of the bulk constants; the default: 'mie' costs about 3x the time and changed the
#: presets' chroma little, docs/model.md §2.4) or 'mie' (pigment crystals scattering and
#: absorbing in the matrix, docs/model.md §2.4).
COATING_OPTICS = ("uniform", "mie")

#: Optical constants as a function ``(material, wavelength_nm) -> n + ik`` (the default is
#: :func:`sandlight.optics.complex_index`).
OpticalConstants = Callable[[str, float], complex]


@runtime_checkable
class Traceable(Protocol):
    """Anything the engine can trace: a native medium per wavelength, and a description.

    Implemented by :class:`~sandlight.physics.media.SandMedium` (a sand sample's composition,
    on the fly with a path memory), :class:`~sandlight.physics.media.PackedSand` (an explicit
    packing), :class:`~sandlight.physics.media.IsotropicScatterers`,
    :class:`~sandlight.physics.media.LambertianSurface` and
    :class:`~sandlight.physics.powder.Powder`; a user class with these two methods works too.
    """

    def medium(self, wavelength_nm: float) -> _native.Medium:
        """The native medium at vacuum wavelength ``wavelength_nm`` (nm)."""
        ...

    def describe(self) -> dict:
        """What is traced, as a JSON-serialisable dict recorded in the results (a sand medium
        adds ``geometry`` and ``memory`` when they are not the defaults)."""
        ...


@functools.lru_cache(maxsize=8192)
def shipped_index(material: str, wavelength_nm: float) -> complex:
    """:func:`sandlight.optics.complex_index` of ``material`` at one wavelength, as a complex,
    remembered: the media of a spectrum ask for the same few materials at every wavelength, and
    every training sample for the same wavelengths again (a table look-up costs tens of µs).
    Other constants are given as ``optical_constants`` (or this name replaced, as
    scripts/studies/derive_constants.py does): replacing ``complex_index`` would meet the
    remembered values."""
    return complex(complex_index(material, wavelength_nm))


@functools.lru_cache(maxsize=1024)
def _encounter_quantiles(sizes: SizeDistribution) -> tuple[float, ...]:
    """The size table the engine samples (:meth:`SizeDistribution.encounter_quantiles`), the same
    at every wavelength: computed once per distribution (a frozen dataclass, the key) rather than
    once per native medium."""
    return tuple(sizes.encounter_quantiles().tolist())


def absorption_per_mm(k: float, wavelength_nm: float) -> float:
    """α = 4πk/λ in mm⁻¹ (λ in nm)."""
    return 4.0 * np.pi * k / (wavelength_nm * 1e-6)


def _mix(materials: dict, wavelength_nm: float, index: OpticalConstants) -> complex:
    return sum(v * complex(index(m, wavelength_nm)) for m, v in materials.items())


def with_host_absorption(index: OpticalConstants, factor: float) -> OpticalConstants:
    """``index`` with the quartz host's k multiplied by ``factor`` (n unchanged); ``index``
    itself when ``factor`` is 1."""
    if factor == 1.0:
        return index

    def scaled(material: str, wavelength_nm: float) -> complex:
        m = complex(index(material, wavelength_nm))
        return complex(m.real, m.imag * factor) if material == HOST_MATERIAL else m

    return scaled


def _optical_index(comp: Composition, optical_constants: OpticalConstants | None) -> OpticalConstants:
    # The shipped (or given) constants with the composition's host absorption, for every material.
    return with_host_absorption(shipped_index if optical_constants is None else optical_constants, comp.host_absorption)


def _pore_indices(comp: Composition, index: OpticalConstants) -> list[Callable[[float], float]]:
    """The real indices of the pore media a fine particle can sit in: air, and water when
    pores can be water-filled."""
    air = [lambda _wavelength_nm: 1.0]
    if comp.water_filled_probability == 0.0:
        return air
    return [*air, lambda wavelength_nm: complex(index("water", wavelength_nm)).real]


def _is_volume_scatterer(p: Population) -> bool:
    return p.name in IRON_OXIDE_PARTICLES


def mie_majorants(comp: Composition, optical_constants: OpticalConstants | None = None) -> tuple[float | None, ...]:
    """Per population of ``comp``, the majorant efficiency Q_max of a Mie volume scatterer (the
    iron-oxide particles of the ``particles`` form, :func:`sandlight.physics.fine_particles.majorant`),
    None for the others. Wavelength independent: computed once per medium."""
    index = _optical_index(comp, optical_constants)
    pores = _pore_indices(comp, index)
    return tuple(
        majorant(lambda w, p=p: _mix(p.core, w, index), pores, size_nodes_um(p)) if _is_volume_scatterer(p) else None
        for p in comp.populations
    )


def _volume_scatterers(
    comp: Composition, wavelength_nm: float, index: OpticalConstants, majorants: tuple[float | None, ...]
) -> list[tuple | None]:
    """The binding's ``volume_scatterers``: per population None, or (Q_max, optics relative to
    air, optics relative to water or None), each optics (Q̄_ext/Q_max, ω, μ nodes, phase)."""

    def optics(p: Population, pore_n: float, q_max: float) -> tuple:
        o = mie_optics(_mix(p.core, wavelength_nm, index), pore_n, size_nodes_um(p), wavelength_nm)
        return check_below_majorant(o, q_max, wavelength_nm), o.albedo, o.mu.tolist(), o.phase.tolist()

    pores = [n(wavelength_nm) for n in _pore_indices(comp, index)]
    out = []
    for p, q_max in zip(comp.populations, majorants):
        if q_max is None:
            out.append(None)
            continue
        water = optics(p, pores[1], q_max) if len(pores) > 1 else None
        out.append((q_max, optics(p, pores[0], q_max), water))
    return out


def native_medium(
    comp: Composition,
    wavelength_nm: float,
    memory: str = "none",
    *,
    optical_constants: OpticalConstants | None = None,
    coating_optics: str = "uniform",
    pigment_diameter_um: float = PIGMENT_DIAMETER_UM,
    particle_optics: str = DEFAULT_PARTICLE_OPTICS,
    majorants: tuple[float | None, ...] | None = None,
) -> _native.Medium:
    """The native medium of composition ``comp`` at ``wavelength_nm`` (nm, vacuum).

    ``memory`` is the on-the-fly engine's near-surface path memory, 'none' (the classic model),
    'channel', 'cut' or 'packed' (docs/geometry.md). ``optical_constants`` replaces the shipped
    tables (:func:`sandlight.optics.complex_index`), e.g. for a what-if run; the composition's
    ``host_absorption`` applies to either. ``coating_optics`` is one of :data:`COATING_OPTICS`;
    ``pigment_diameter_um`` the pigment crystals' diameter (µm) for 'mie'. ``particle_optics``
    is one of :data:`~sandlight.physics.fine_particles.PARTICLE_OPTICS`: with 'mie' the iron-oxide
    particles are volume scatterers with Mie optics, with ``majorants`` from
    :func:`mie_majorants` (computed here when None; pass them to build many wavelengths).
    """
    check_choice("coating_optics", coating_optics, COATING_OPTICS)
    check_choice("particle_optics", particle_optics, PARTICLE_OPTICS)
    index = _optical_index(comp, optical_constants)
    mie_particles = particle_optics == "mie"
    if mie_particles and majorants is None:
        majorants = mie_majorants(comp, optical_constants)
    probs = comp.encounter_probabilities()
    quantiles, aspect, core_n, core_k, core_a, coat_n, coat_a, coat_t = ([] for _ in range(8))
    coat_s, coat_g, coat_f, core_s = [], [], [], []
    for p in comp.populations:
        core = _mix(p.core, wavelength_nm, index)
        quantiles.append(_encounter_quantiles(p.sizes))
        aspect.append(p.aspect_ratio)
        core_n.append(core.real)
        core_k.append(core.imag)
        core_a.append(absorption_per_mm(core.imag, wavelength_nm))
        core_s.append(p.core_scattering_per_mm)
        coated = bool(p.coating) and p.coating_thickness_mm > 0
        if coated and coating_optics == "mie":
            c = pigmented_coating(p.coating, wavelength_nm, pigment_diameter_um, optical_constants=index)
            n, a, sca, g = c.n, c.absorption_per_mm, c.scattering_per_mm, c.asymmetry
        elif coated:
            c = _mix(p.coating, wavelength_nm, index)
            n, a, sca, g = c.real, absorption_per_mm(c.imag, wavelength_nm), 0.0, 0.0
        else:
            n, a, sca, g = 1.0, 0.0, 0.0, 0.0
        coat_n.append(n)
        coat_a.append(a)
        coat_s.append(sca)
        coat_g.append(g)
        coat_t.append(p.coating_thickness_mm if coated else 0.0)
        coat_f.append(comp.coating_coverage if coated else 1.0)
    water = complex(index("water", wavelength_nm))
    return _native.Medium.particulate(
        probs,
        quantiles,
        aspect,
        core_n,
        core_k,
        core_a,
        coat_n,
        coat_a,
        coat_t,
        comp.mean_free_path_mm,
        water.real,
        absorption_per_mm(water.imag, wavelength_nm),
        comp.film_thickness_mm,
        comp.water_filled_probability,
        comp.depth_mm,
        memory=memory,
        film_coverage=comp.film_coverage,
        coating_coverage=coat_f,
        **({"core_scattering_per_mm": core_s} if any(core_s) else {}),
        **({"coating_scattering_per_mm": coat_s, "coating_asymmetry": coat_g} if coating_optics == "mie" else {}),
        **({"volume_scatterers": _volume_scatterers(comp, wavelength_nm, index, majorants)} if mie_particles else {}),
    )
