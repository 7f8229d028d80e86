"""Iron-oxide particles as Lorenz–Mie volume scatterers (``particle_optics='mie'``,
docs/model.md §2.4 item 8): the Mie quantities the engine is given, energy conservation, the
unchanged default, and the refusals."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import sandlight
from sandlight import _native
from sandlight.errors import ParameterError
from sandlight.optics import complex_index
from sandlight.physics.composition import compose
from sandlight.physics.fine_particles import MAJORANT_MARGIN, majorant, mie_optics, size_nodes_um
from sandlight.physics.media import SandMedium
from sandlight.physics.medium import mie_majorants, native_medium

miepython = pytest.importorskip("miepython")

GDS76 = "gds76-hematite-quartz"


def same_shape(p: np.ndarray, q: np.ndarray) -> None:
    """p ∝ q to 1e-7 (the engine normalises the tabulated phase function's interpolant itself)."""
    np.testing.assert_allclose(p / p.sum(), q / q.sum(), rtol=1e-7, atol=1e-9 * q.max() / q.sum())


def reference(m: complex, x: float, mu: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Q_ext, Q_sca and p(μ) (sr⁻¹) from miepython, which writes m = n − ik."""
    q_ext, q_sca, _, _ = miepython.efficiencies_mx(np.conj(m), x)
    return q_ext, q_sca, miepython.i_unpolarized(np.conj(m), x, mu, norm="one")


@pytest.mark.parametrize(
    ("core", "pore_n", "d_um", "wavelength_nm"),
    [
        (complex_index("hematite", 500.0), 1.0, 2.5, 500.0),  # x = 5π exactly: sin x ≈ 0
        (complex_index("hematite", 600.0), 1.0, 0.5, 600.0),
        (complex_index("hematite", 1500.0), 1.333, 1.0, 1500.0),  # in water, nearly lossless
        (complex_index("goethite", 450.0), 1.0, 0.2, 450.0),
        (2.4 + 0.6j, 1.0, 3.0, 400.0),
    ],
)
def test_the_engines_mie_optics_agree_with_miepython(core, pore_n, d_um, wavelength_nm):
    o = mie_optics(core, pore_n, np.array([d_um]), wavelength_nm)
    m, x = core / pore_n, np.pi * d_um * 1e3 * pore_n / wavelength_nm
    q_ext, q_sca, p = reference(m, x, o.mu)
    assert o.q_ext == pytest.approx(q_ext, rel=1e-8)
    assert o.q_sca == pytest.approx(q_sca, rel=1e-8)
    assert o.albedo == pytest.approx(q_sca / q_ext, rel=1e-8)
    same_shape(o.phase, p)


def test_size_averaged_optics_are_means_over_the_sizes_met():
    # Q̄ = mean of Q over the sizes (equal weights), phase the Q_sca-weighted mean.
    core, d = complex_index("hematite", 550.0), np.array([0.3, 0.6, 1.2])
    o = mie_optics(core, 1.0, d, 550.0)
    refs = [reference(core, np.pi * di * 1e3 / 550.0, o.mu) for di in d]
    assert o.q_ext == pytest.approx(np.mean([r[0] for r in refs]), rel=1e-8)
    assert o.q_sca == pytest.approx(np.mean([r[1] for r in refs]), rel=1e-8)
    mixed = sum(r[1] * r[2] for r in refs) / sum(r[1] for r in refs)
    same_shape(o.phase, mixed)


def test_the_majorant_bounds_the_extinction_at_every_wavelength_of_the_tables():
    medium = SandMedium.from_sample(sandlight.SandSample.preset(GDS76), particle_optics="mie")
    names = [p.name for p in medium.composition.populations]
    q_max = medium.majorants[names.index("hematite particles")]
    assert [q is None for q in medium.majorants] == [n != "hematite particles" for n in names]
    pop = medium.composition.populations[names.index("hematite particles")]
    wl = np.arange(352.5, 2500.0, 5.0)  # between the majorant's grid nodes
    q = [mie_optics(complex_index("hematite", w), 1.0, size_nodes_um(pop), w).q_ext for w in wl]
    assert max(q) <= q_max
    assert max(q) * MAJORANT_MARGIN > 0.9 * q_max  # a bound, not a wild one
    assert majorant(lambda w: complex_index("hematite", w), [lambda w: 1.0], size_nodes_um(pop)) == q_max


def lossless(material: str, wavelength_nm: float) -> complex:
    return complex(complex_index(material, wavelength_nm).real, 0.0)


@pytest.mark.parametrize("memory", ["none", "packed"])
@pytest.mark.parametrize("saturation", [0.0, 0.6])
def test_a_lossless_mie_particle_medium_returns_all_light_that_is_not_capped(memory, saturation):
    # k = 0 everywhere (hematite too: ω = 1), semi-infinite, dry and with water-filled pores.
    sample = sandlight.SandSample.preset(GDS76).replace(saturation=saturation, iron_oxide_particle_size_um=0.5)
    medium = SandMedium.from_sample(sample, memory, particle_optics="mie", optical_constants=lossless)
    # share=False: integer counts (a shared run tallies fixed-point estimates).
    r = sandlight.reflectance(medium, [450.0, 650.0], rays=800, seed=2, max_events=20_000, share=False, progress=False)
    c = r.counts
    assert np.array_equal(c["absorbed"], [0, 0]) and np.array_equal(c["transmitted"], [0, 0])
    assert np.array_equal(c["escaped"] + c["capped"], c["launched"])
    assert np.all(c["capped"] < 0.05 * c["launched"])


#: Escaped counts of 1500 rays, seed 3, share=False, normal incidence, at 420, 550, 650, 1450
#: and 2200 nm, from the engine before particle_optics existed (commit de4d41f).
BEFORE = {
    "none": [479, 469, 769, 1287, 1312],
    "packed": [391, 390, 717, 1258, 1257],
}


@pytest.mark.parametrize("memory", ["none", "packed"])
def test_geometric_particles_trace_as_before_particle_optics_existed(memory):
    wl = [420.0, 550.0, 650.0, 1450.0, 2200.0]
    sample = sandlight.SandSample.preset(GDS76)
    runs = [
        sandlight.reflectance(
            SandMedium.from_sample(sample, memory, **kw), wl, rays=1500, seed=3, share=False, progress=False
        )
        for kw in ({}, {"particle_optics": "geometric"})
    ]
    assert np.array_equal(runs[0].counts["escaped"], BEFORE[memory])
    assert np.array_equal(runs[0].values, runs[1].values) and np.array_equal(runs[0].stderr, runs[1].stderr)


def test_particle_optics_is_recorded_only_when_not_the_default():
    sample = sandlight.SandSample.preset(GDS76)
    assert "particle_optics" not in SandMedium.from_sample(sample).describe()
    assert SandMedium.from_sample(sample, particle_optics="mie").describe()["particle_optics"] == "mie"


def test_bad_values_are_refused_with_the_parameter_name():
    sample = sandlight.SandSample.preset(GDS76)
    with pytest.raises(ParameterError, match="particle_optics"):
        SandMedium.from_sample(sample, particle_optics="wave")
    with pytest.raises(ParameterError, match="particle_optics"):
        native_medium(compose(sample), 550.0, particle_optics="wave")
    for memory in ("channel", "cut"):
        with pytest.raises(ParameterError, match="memory"):
            SandMedium.from_sample(sample, memory, particle_optics="mie")
    # The binding: memory, and the volume scatterers' own values.
    comp = compose(sample)
    with pytest.raises(ParameterError, match="memory"):
        native_medium(comp, 550.0, "cut", particle_optics="mie")
    bad = [None] * (len(comp.populations) - 1) + [(2.0, (1.5, 0.5, [-1.0, 1.0], [1.0, 1.0]), None)]
    with pytest.raises(ParameterError, match="extinction"):
        _native.Medium.particulate(*particulate_args(comp), volume_scatterers=bad)
    good = (2.0, (0.5, 0.5, [-1.0, 1.0], [1.0, 1.0]), None)
    with pytest.raises(ParameterError, match="volume_scatterers"):
        _native.Medium.particulate(*particulate_args(comp), volume_scatterers=[good])


def particulate_args(comp) -> list:
    """Positional arguments of the binding for ``comp``: its geometry, clear cores, dry, no
    coatings (enough for the refusals)."""
    n = len(comp.populations)
    optics = [[1.5] * n, [0.0] * n, [0.0] * n, [1.0] * n, [0.0] * n, [0.0] * n]
    geometry = [
        comp.encounter_probabilities(),
        [p.sizes.encounter_quantiles().tolist() for p in comp.populations],
        [p.aspect_ratio for p in comp.populations],
    ]
    return [*geometry, *optics, comp.mean_free_path_mm, 1.333, 0.0, 0.0, 0.0, comp.depth_mm]


def test_majorants_do_not_depend_on_the_wavelengths_of_a_run():
    medium = SandMedium.from_sample(sandlight.SandSample.preset(GDS76), particle_optics="mie")
    assert mie_majorants(medium.composition) == medium.majorants
    other = dataclasses.replace(medium)
    assert other.majorants == medium.majorants
