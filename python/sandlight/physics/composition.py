"""From a sample's measurable parameters to its particle populations, by mass balance.

Wavelength-independent: what particles there are, how big, where the iron oxide sits, how thick
the coatings and water films are, and the mean free path of the pore space. Every assumption is
listed in docs/transport.md ("From the sample to the particles").

Per unit mass of solids:

* iron oxide m_fe = ``iron_oxide`` (hematite m_fe·r, goethite m_fe·(1 − r), r = ``hematite_ratio``),
  magnetite m_mag = ``magnetite``;
* form ``coating``: the iron oxide sits in a kaolinite matrix coating every host particle (sand,
  silt and clay), iron-oxide volume share ``coating_iron_share``: coating volume V_c = V_fe / share,
  of which V_c − V_fe is kaolinite; thickness t_c = V_c / (total host surface) — a uniform film;
* form ``mixed``: the iron oxide is dispersed inside the quartz grains (volume fraction
  V_fe/(V_fe + V_quartz));
* form ``particles``: separate spherical hematite and goethite particles of diameter
  ``iron_oxide_particle_size_um``;
* the rest (host) is split by the USDA separates: sand-sized quartz grains (log-normal by mass,
  median ``grain_size``, geometric sd ``grain_size_spread``, 0.05–2 mm), silt-sized quartz
  (log-uniform by mass, 0.002–0.05 mm) and clay-sized kaolinite (log-uniform, 0.0002–0.002 mm);
* magnetite: separate grains with the sand grains' size distribution.

Pore space (docs/model.md §2.1): mean free path ℓ = 4φ / [(1 − φ) Σᵢ vᵢ ⟨Sᵢ⟩/⟨Vᵢ⟩], with
vᵢ the volume fractions of the solids; a ray meets type i with probability ∝ vᵢ⟨Sᵢ⟩/⟨Vᵢ⟩.
Water (§2.5): up to ``film_saturation`` S_f the water forms films; with ``films='pendular'`` it
is pendular: rings at the grain contacts that wet a fraction f of the particle surface
(:func:`sandlight.physics.pendular.film_coverage` of min(S, S_f)), where it lies as a film of
thickness t_w = φ min(S, S_f) / [f (1 − φ) Σᵢ vᵢ⟨Sᵢ⟩/⟨Vᵢ⟩] = min(S, S_f) ℓ/(4f) (the same water
volume), the default (:data:`DEFAULT_FILMS`); with ``films='uniform'`` (the model before
issue 17) f = 1, a film on every particle. Beyond S_f, a pore is water-filled with
probability (S − S_f)/(1 − S_f).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.checks import check_choice
from sandlight.errors import ParameterError
from sandlight.optics import DENSITY_G_CM3
from sandlight.physics.pendular import film_coverage
from sandlight.physics.sizes import SizeDistribution, lognormal_mass_mean_inverse_diameter, spheroid_surface_factor

if TYPE_CHECKING:
    from sandlight.sample import SandSample

SAND_RANGE_MM = (0.05, 2.0)
SILT_RANGE_MM = (0.002, 0.05)
#: The populations of the ``particles`` form: separate hematite and goethite particles.
IRON_OXIDE_PARTICLES = ("hematite particles", "goethite particles")
#: The material of the host grains (sand and silt cores): what ``host_absorption`` scales and
#: ``host_scattering`` fills.
HOST_MATERIAL = "quartz"
CLAY_RANGE_MM = (0.0002, 0.002)


@dataclass(frozen=True)
class Population:
    """One particle type of a sample.

    Attributes
    ----------
    name : str
        e.g. ``"quartz sand"``.
    volume_fraction : float
        Fraction of the solid volume.
    sizes : SizeDistribution
        Mass size distribution of the volume-equivalent diameter (mm).
    aspect_ratio : float
        Prolate spheroid ε = c/a.
    core : dict[str, float]
        Volume fractions of the core's materials (names of ``sandlight.optics``), summing to 1.
    coating : dict[str, float]
        Volume fractions of the coating's materials; empty for none.
    coating_thickness_mm : float
    surface_per_volume_per_mm : float
        ⟨S⟩/⟨V⟩ of this population (mm⁻¹).
    core_scattering_per_mm : float
        Scattering coefficient of the inclusions inside the cores (mm⁻¹; docs/model.md §2.4
        item 9), 0 for clear cores.
    """

    name: str
    volume_fraction: float
    sizes: SizeDistribution
    aspect_ratio: float
    core: dict = field(default_factory=dict)
    coating: dict = field(default_factory=dict)
    coating_thickness_mm: float = 0.0
    surface_per_volume_per_mm: float = 0.0
    core_scattering_per_mm: float = 0.0


@dataclass(frozen=True)
class Composition:
    """The particle populations and pore space of a sample (wavelength independent).

    ``host_absorption`` is the factor on the k of the quartz host (``SandSample.host_absorption``;
    applied where the native medium is built, :func:`sandlight.physics.medium.native_medium`).
    ``coating_coverage`` is the fraction of a coated particle's surface that carries the coating
    (``SandSample.coating_coverage``); the populations' ``coating_thickness_mm`` is the thickness
    on those patches.
    """

    populations: tuple
    porosity: float
    mean_free_path_mm: float
    film_thickness_mm: float
    water_filled_probability: float
    depth_mm: float
    #: Fraction of the particle surface facing an air-filled pore that the film wets.
    film_coverage: float = 1.0
    host_absorption: float = 1.0
    #: Fraction of a coated particle's surface that carries the coating (drawn per surface point).
    coating_coverage: float = 1.0

    def encounter_probabilities(self) -> list[float]:
        """P(type i) ∝ vᵢ⟨Sᵢ⟩/⟨Vᵢ⟩ (docs/model.md §2.2)."""
        w = [p.volume_fraction * p.surface_per_volume_per_mm for p in self.populations]
        total = sum(w)
        return [x / total for x in w]


def surface_per_volume_per_mm(sizes: SizeDistribution, aspect_ratio: float) -> float:
    """⟨S⟩/⟨V⟩ (mm⁻¹) of prolate spheroids of aspect ratio ε with mass size distribution ``sizes``.

    ⟨S⟩/⟨V⟩ = 6 f(ε) ⟨D²⟩_n/⟨D³⟩_n = 6 f(ε) E_m[1/D] (sphere: S/V = 6/D), f the spheroid's surface
    over that of the sphere of equal volume.
    """
    return 6.0 * spheroid_surface_factor(aspect_ratio) * sizes.mass_mean_inverse_diameter()


def population(
    name: str,
    volume_fraction: float,
    sizes: SizeDistribution,
    aspect_ratio: float,
    core: dict,
    coating: dict | None = None,
    coating_thickness_mm: float = 0.0,
    core_scattering_per_mm: float = 0.0,
) -> Population:
    """A :class:`Population` with its ⟨S⟩/⟨V⟩ computed from its sizes and shape."""
    return Population(
        name=name,
        volume_fraction=volume_fraction,
        sizes=sizes,
        aspect_ratio=aspect_ratio,
        core=core,
        coating=coating or {},
        coating_thickness_mm=coating_thickness_mm,
        surface_per_volume_per_mm=surface_per_volume_per_mm(sizes, aspect_ratio),
        core_scattering_per_mm=core_scattering_per_mm,
    )


def mean_free_path_mm(populations: tuple | list, porosity: float) -> float:
    """Mean free path in the pore space ℓ = 4φ / [(1 − φ) Σᵢ vᵢ ⟨Sᵢ⟩/⟨Vᵢ⟩] (mm; docs/model.md
    §2.1), vᵢ the populations' volume fractions of the solids, φ the porosity."""
    surface = sum(p.volume_fraction * p.surface_per_volume_per_mm for p in populations)
    return 4.0 * porosity / ((1.0 - porosity) * surface)


@dataclass(frozen=True)
class SolidVolumes:
    """Volumes per gram of solids (cm³ g⁻¹) by mass balance (module docstring): floats, or
    arrays for a batch of samples."""

    hematite: float | np.ndarray
    goethite: float | np.ndarray
    #: The coating (iron oxide and its kaolinite matrix); 0 without one.
    coating: float | np.ndarray
    #: Mass of the host solids (sand, silt, clay) per gram of solids, g g⁻¹.
    host_mass: float | np.ndarray
    sand: float | np.ndarray
    silt: float | np.ndarray
    clay: float | np.ndarray
    magnetite: float | np.ndarray

    @property
    def iron_oxide(self) -> float | np.ndarray:
        return self.hematite + self.goethite


def solid_volumes(
    iron_oxide: ArrayLike,
    hematite_ratio: ArrayLike,
    magnetite: ArrayLike,
    coated: ArrayLike,
    coating_iron_share: ArrayLike,
    sand: ArrayLike,
    silt: ArrayLike,
    clay: ArrayLike,
) -> SolidVolumes:
    """The mass balance of the module docstring, for floats or arrays (mass fractions; ``coated``
    1 for the form 'coating', else 0): V_fe = m_fe r/ρ_hem + m_fe (1 − r)/ρ_goe, coating
    V_c = V_fe/share, host mass 1 − m_fe − m_mag − (V_c − V_fe) ρ_kaol, split by the separates."""
    rho = DENSITY_G_CM3
    v_hem = iron_oxide * hematite_ratio / rho["hematite"]
    v_goe = iron_oxide * (1.0 - hematite_ratio) / rho["goethite"]
    v_coat = coated * (v_hem + v_goe) / coating_iron_share
    m_host = 1.0 - iron_oxide - magnetite - (v_coat - coated * (v_hem + v_goe)) * rho["kaolinite"]
    return SolidVolumes(
        hematite=v_hem,
        goethite=v_goe,
        coating=v_coat,
        host_mass=m_host,
        sand=sand * m_host / rho["quartz"],
        silt=silt * m_host / rho["quartz"],
        clay=clay * m_host / rho["kaolinite"],
        magnetite=magnetite / rho["magnetite"],
    )


#: Where the film water sits: 'uniform' (a film on every particle, the model before issue 17)
#: or 'pendular' (rings at the grain contacts, docs/model.md §2.5, docs/wet-sand.md).
FILM_MODELS = ("uniform", "pendular")
#: The film model when none is asked for: the one the shipped predictor bank is trained with.
DEFAULT_FILMS = "pendular"


def compose(sample: SandSample, films: str = DEFAULT_FILMS) -> Composition:
    """Particle populations of ``sample`` (a :class:`sandlight.SandSample`) by mass balance;
    ``films`` (one of :data:`FILM_MODELS`) says where its film water sits."""
    rho = DENSITY_G_CM3
    form = sample.iron_oxide_form
    vol = solid_volumes(
        sample.iron_oxide,
        sample.hematite_ratio,
        sample.magnetite,
        float(form == "coating"),
        sample.coating_iron_share,
        sample.sand,
        sample.silt,
        sample.clay,
    )
    v_hem, v_goe, v_fe = vol.hematite, vol.goethite, vol.iron_oxide
    if vol.host_mass <= 0.0:
        rest = 1.0 - sample.iron_oxide - sample.magnetite  # the host and the coating's kaolinite
        raise ParameterError(
            "coating_iron_share",
            sample.coating_iron_share,
            f"too small for iron_oxide = {sample.iron_oxide} and magnetite = {sample.magnetite}: the kaolinite "
            f"coating would outweigh the solids; need coating_iron_share > "
            f"{v_fe * rho['kaolinite'] / (rest + v_fe * rho['kaolinite']):.4g}",
        )

    eps = sample.aspect_ratio
    sand_sizes = SizeDistribution(
        "lognormal", *SAND_RANGE_MM, median_mm=sample.grain_size, spread=sample.grain_size_spread
    )
    silt_sizes = SizeDistribution("loguniform", *SILT_RANGE_MM)
    clay_sizes = SizeDistribution("loguniform", *CLAY_RANGE_MM)

    v_sand, v_silt, v_clay, v_magn = vol.sand, vol.silt, vol.clay, vol.magnetite

    quartz_core = {"quartz": 1.0}
    coating, t_coat = {}, 0.0
    sv_sand = surface_per_volume_per_mm(sand_sizes, eps)
    sv_silt = surface_per_volume_per_mm(silt_sizes, eps)
    if form == "mixed" and v_fe > 0:
        v_q = v_sand + v_silt
        total = v_q + v_fe
        quartz_core = {"quartz": v_q / total, "hematite": v_hem / total, "goethite": v_goe / total}
    elif form == "coating" and v_fe > 0:
        v_coat = vol.coating
        # The coating covers every host particle, clay included: the iron oxide of red and yellow
        # sands sits in clay-sized coatings and aggregates, so clean white clay beside stained
        # grains is not what such sands are (docs/transport.md). Volumes are per gram of solids
        # (cm³) and S/V in mm⁻¹, so the volume unit cancels: t in mm. On a fraction f of the
        # surface (coating_coverage) the same volume is t/f thick: t = V_c / (f S_host).
        host_surface = v_sand * sv_sand + v_silt * sv_silt + v_clay * surface_per_volume_per_mm(clay_sizes, eps)
        covered = sample.coating_coverage * host_surface
        t_coat = v_coat / covered if covered > 0 else 0.0
        coating = {"hematite": v_hem / v_coat, "goethite": v_goe / v_coat, "kaolinite": (v_coat - v_fe) / v_coat}

    pops = []

    def add(
        name: str,
        volume: float,
        sizes: SizeDistribution,
        aspect: float,
        core: dict[str, float],
        coat: dict[str, float] | None = None,
        t: float = 0.0,
    ) -> None:
        if volume > 0:
            # The host's inclusions in proportion to its share of the core (item 9 of §2.4).
            sigma = sample.host_scattering * core.get(HOST_MATERIAL, 0.0)
            pops.append(population(name, volume, sizes, aspect, core, coat, t, sigma))

    add("quartz sand", v_sand, sand_sizes, eps, quartz_core, coating, t_coat)
    add("quartz silt", v_silt, silt_sizes, eps, quartz_core, coating, t_coat)
    add("kaolinite clay", v_clay, clay_sizes, eps, {"kaolinite": 1.0}, coating, t_coat)
    add("magnetite", v_magn, sand_sizes, eps, {"magnetite": 1.0})
    if form == "particles":
        d = sample.iron_oxide_particle_size_um * 1e-3
        pigment = SizeDistribution("lognormal", d, d, median_mm=d, spread=1.0)
        for name, volume, material in zip(IRON_OXIDE_PARTICLES, (v_hem, v_goe), ("hematite", "goethite")):
            add(name, volume, pigment, 1.0, {material: 1.0})

    v_total = sum(p.volume_fraction for p in pops)
    pops = [dataclasses.replace(p, volume_fraction=p.volume_fraction / v_total) for p in pops]
    phi = sample.porosity
    ell = mean_free_path_mm(pops, phi)

    s = sample.saturation
    s_film = min(s, sample.film_saturation)
    coverage = film_coverage(s_film, phi) if check_choice("films", films, FILM_MODELS) == "pendular" else 1.0
    film = s_film * ell / (4.0 * coverage) if coverage > 0.0 else 0.0
    filled = (s - s_film) / (1.0 - s_film) if s_film < 1.0 else 0.0
    return Composition(
        populations=tuple(pops),
        porosity=phi,
        mean_free_path_mm=ell,
        film_thickness_mm=film,
        water_filled_probability=min(max(filled, 0.0), 1.0),
        depth_mm=sample.depth_mm,
        film_coverage=coverage if coverage > 0.0 else 1.0,
        host_absorption=sample.host_absorption,
        coating_coverage=sample.coating_coverage,
    )


@functools.cache
def _loguniform_mean_inverse_diameter(d_min_mm: float, d_max_mm: float) -> float:
    """E_m[1/D] of the silt and clay separates (fixed ranges: computed once)."""
    return SizeDistribution("loguniform", d_min_mm, d_max_mm).mass_mean_inverse_diameter()


def length_scales(columns: Mapping[str, ArrayLike]) -> dict[str, np.ndarray]:
    """The lengths of :func:`compose` for a batch of samples, as arrays (vectorised).

    ``columns`` holds every SandSample parameter as an array of one length (the layout of
    :func:`sandlight.predictor.samples.sample_columns`; ``iron_oxide_form`` as names). Returns,
    in mm unless said:

    * ``mean_free_path_mm``: ℓ of the pore space;
    * ``coating_thickness_mm``: t_c of the coating on its patches (0 unless form 'coating');
    * ``film_thickness_mm``: min(S, S_f) ℓ/4, the film if it wet every surface (films='uniform';
      the pendular film is this over its coverage);
    * ``water_filled_probability``: (S − S_f)/(1 − S_f), within [0, 1] (fraction);
    * ``core_iron_path_mm``: iron-oxide volume share of the quartz cores times the sand's Sauter
      diameter 6/(⟨S⟩/⟨V⟩), the scale of the iron's absorption inside a grain (0 unless 'mixed').

    The same formulas as :func:`compose`; E_m[1/D] of the sand in closed form
    (:func:`~sandlight.physics.sizes.lognormal_mass_mean_inverse_diameter`), where ``compose``
    integrates it numerically (they agree to 10⁻⁶, tests/physics/test_composition.py). The
    predictors take these as inputs (docs/spectral-predictor.md, "Method", step 3).
    """
    form = np.asarray(columns["iron_oxide_form"]).astype(str)
    x = {k: np.asarray(v, dtype=float) for k, v in columns.items() if k != "iron_oxide_form"}
    eps = x["aspect_ratio"]
    vol = solid_volumes(
        x["iron_oxide"],
        x["hematite_ratio"],
        x["magnetite"],
        (form == "coating").astype(float),
        x["coating_iron_share"],
        x["sand"],
        x["silt"],
        x["clay"],
    )
    shape = 6.0 * spheroid_surface_factor(eps)
    sv_sand = shape * lognormal_mass_mean_inverse_diameter(x["grain_size"], x["grain_size_spread"], *SAND_RANGE_MM)
    sv_silt = shape * _loguniform_mean_inverse_diameter(*SILT_RANGE_MM)
    sv_clay = shape * _loguniform_mean_inverse_diameter(*CLAY_RANGE_MM)
    host_surface = vol.sand * sv_sand + vol.silt * sv_silt + vol.clay * sv_clay
    # Separate iron-oxide particles (spheres of one size) are solids of their own.
    particles = np.where(form == "particles", vol.iron_oxide, 0.0)
    sv_particles = 6.0 / (x["iron_oxide_particle_size_um"] * 1e-3)
    solids = vol.sand + vol.silt + vol.clay + vol.magnetite + particles
    surface = (host_surface + vol.magnetite * sv_sand + particles * sv_particles) / solids
    phi = x["porosity"]
    ell = 4.0 * phi / ((1.0 - phi) * surface)
    covered = x["coating_coverage"] * host_surface
    t_coat = np.where(vol.coating > 0, vol.coating / np.where(covered > 0, covered, 1.0), 0.0)
    s = x["saturation"]
    s_film = np.minimum(s, x["film_saturation"])
    filled = np.where(s_film < 1.0, (s - s_film) / np.where(s_film < 1.0, 1.0 - s_film, 1.0), 0.0)
    mixed = form == "mixed"
    share = np.where(mixed, vol.iron_oxide / (vol.sand + vol.silt + vol.iron_oxide), 0.0)
    return {
        "mean_free_path_mm": ell,
        "coating_thickness_mm": t_coat,
        "film_thickness_mm": s_film * ell / 4.0,
        "water_filled_probability": np.clip(filled, 0.0, 1.0),
        "core_iron_path_mm": share * 6.0 / sv_sand,
    }
