"""Spectral path sharing (docs/transport.md, "Spectral path sharing"): shared spectra agree with
independent runs in expectation, their standard errors are right, and they are deterministic."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.optics import complex_index
from sandlight.physics.media import IsotropicScatterers, PackedSand, SandMedium, as_traceable
from sandlight.physics.medium import native_medium
from sandlight.physics.packing import generate_packing, reference_grain_mm
from sandlight.physics.powder import Powder
from sandlight.physics.spectral_groups import direction_indices, spectral_groups


def absorption_only(name):
    """The preset (or sand medium) with every real index frozen at its 550 nm value: only
    absorption varies."""

    def index(material: str, wavelength_nm: float) -> complex:
        return complex(complex_index(material, 550.0).real, complex_index(material, wavelength_nm).imag)

    return dataclasses.replace(as_traceable(name), optical_constants=index)


def z_scores(traced, wl, rays: int, seeds: range) -> np.ndarray:
    """z = (shared − independent)/√(se_s² + se_i²) per (seed, wavelength); each independent run
    has its own seed, so that independent errors are independent."""
    out = []
    for seed in seeds:
        shared = sandlight.reflectance(traced, wl, rays=rays, seed=seed, progress=False)
        assert shared.shared
        for k, lam in enumerate(wl):
            ind = sandlight.reflectance(
                traced, [lam], rays=rays, seed=10_000 + 100 * seed + k, progress=False, share=False
            )
            se = np.hypot(shared.stderr[k], ind.stderr[0])
            out.append((shared.values[k] - ind.values[0]) / se)
    return np.array(out)


def report(z: np.ndarray) -> None:
    """The statistics docs/transport.md quotes (``pytest -rP`` shows them)."""
    print(f"{z.size} z: mean {z.mean():+.3f}, spread {z.std(ddof=1):.3f}, max |z| {np.abs(z).max():.2f}")


def test_absorption_only_media_agree_with_independent_runs():
    # Red dune sand with its indices frozen: iron-oxide absorption makes ρ go from 0.03 to 0.6
    # over 450–650 nm, all six wavelengths in one group.
    traced = absorption_only("red-dune")
    wl = np.linspace(450.0, 650.0, 6)
    assert len(spectral_groups(traced.composition, wl, 0.0, optical_constants=traced.optical_constants)) == 1
    z = z_scores(traced, wl, rays=3000, seeds=range(1, 31))
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def test_real_presets_350_to_2500_nm_agree_with_independent_runs():
    # Real dispersion, grouped by the default tolerance (docs/transport.md reports the bigger
    # run of scripts/studies/spectral_sharing_check.py).
    wl = np.array([350.0, 450.0, 550.0, 700.0, 1000.0, 1300.0, 1700.0, 2100.0, 2500.0])
    z = np.concatenate([z_scores(name, wl, rays=2000, seeds=range(1, 7)) for name in ("red-dune", "yellow-dune")])
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def packed(films: str = "uniform", **sample) -> SandMedium:
    """A sample (``SandSample`` parameters, iron_oxide 0.02 unless given) with memory 'packed'."""
    return SandMedium.from_sample(sandlight.SandSample(**{"iron_oxide": 0.02, **sample}), "packed", films=films)


#: Visible and water bands: with pores filled the water's absorption varies by 10⁴ over them.
WATER_BANDS = np.array([450.0, 550.0, 650.0, 970.0, 1200.0, 1450.0])


def test_packed_memory_dry_agrees_with_independent_runs():
    # The path memory 'packed' (cut surface, pore walls, pair correlation) shared: iron oxide
    # makes ρ go from about 0.1 to 0.6 over 400–700 nm.
    z = z_scores(packed(), np.linspace(400.0, 700.0, 6), rays=1500, seeds=range(1, 21))
    report(z)
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def test_packed_memory_wet_agrees_with_independent_runs():
    # Films only (saturation below film_saturation 0.15) and water-filled pores (through the
    # flat water surface of the cut layer), uniform and pendular films.
    cases = [packed(films, saturation=saturation) for films in ("uniform", "pendular") for saturation in (0.1, 0.6)]
    assert [m.composition.water_filled_probability > 0 for m in cases] == [False, True] * 2
    z = np.concatenate([z_scores(m, WATER_BANDS, rays=600, seeds=range(1, 6)) for m in cases])
    report(z)
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def test_mie_particles_agree_with_independent_runs():
    # GDS76's hematite as 0.5 µm Mie volume scatterers (null, scatter and absorb weights and the
    # phase-function ratio), real indices frozen so that 450–700 nm is one group, classic and
    # packed tracers.
    sample = sandlight.SandSample.preset("gds76-hematite-quartz").replace(iron_oxide_particle_size_um=0.5)
    wl = np.linspace(450.0, 700.0, 6)
    z = []
    for memory in ("none", "packed"):
        medium = SandMedium.from_sample(sample, memory, particle_optics="mie")
        frozen = dataclasses.replace(medium, optical_constants=absorption_only(medium).optical_constants)
        assert len(spectral_groups(frozen.composition, wl, 0.0, optical_constants=frozen.optical_constants)) == 1
        z.append(z_scores(frozen, wl, rays=1500, seeds=range(1, 11)))
    z = np.concatenate(z)
    report(z)
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def test_powders_agree_with_independent_runs():
    # A quartz sieve fraction over 400–700 nm (one group) and hematite over 1000–2500 nm, whose
    # dispersion cuts its six wavelengths into groups [1, 1, 4].
    cases = [(Powder("quartz", (10.0, 100.0)), np.linspace(400.0, 700.0, 6))]
    cases.append((Powder("hematite", 20.0), np.linspace(1000.0, 2500.0, 6)))
    z = np.concatenate([z_scores(p, wl, rays=1500, seeds=range(1, 11)) for p, wl in cases])
    report(z)
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def test_host_inclusions_agree_with_independent_runs():
    # Inclusions in the quartz host (host_scattering, grey: their free paths are geometry) with
    # the absorption of the core and coating varying, classic and packed tracers, indices frozen.
    sample = sandlight.SandSample.preset("red-dune").replace(host_scattering=8.0)
    wl = np.linspace(450.0, 650.0, 6)
    z = []
    for memory in ("none", "packed"):
        medium = SandMedium.from_sample(sample, memory)
        frozen = dataclasses.replace(medium, optical_constants=absorption_only(medium).optical_constants)
        z.append(z_scores(frozen, wl, rays=1500, seeds=range(1, 11)))
    z = np.concatenate(z)
    report(z)
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


@pytest.fixture(scope="module")
def explicit_red_dune() -> PackedSand:
    """red-dune through an explicit packing of its grains in a small box (2 mm, seed 1); its
    fines stay on the fly."""
    comp = as_traceable("red-dune").composition
    pk = generate_packing(
        native_medium(comp, 550.0), reference_mm=reference_grain_mm(comp), lateral_mm=2.0, depth_mm=2.0, seed=1
    )
    return as_traceable("red-dune", geometry="explicit", packing=pk)


def test_explicit_geometry_agrees_with_independent_runs(explicit_red_dune):
    # The explicit reference shared through its packing: absorption only (450–650 nm, ρ from
    # about 0.03 to 0.6, one group), and its real dispersion over 400–700 nm (one group at the
    # default tolerance).
    frozen = absorption_only(explicit_red_dune)
    wl = np.linspace(450.0, 650.0, 6)
    assert len(spectral_groups(frozen.composition, wl, 0.0, optical_constants=frozen.optical_constants)) == 1
    z_frozen = z_scores(frozen, wl, rays=2000, seeds=range(1, 21))
    report(z_frozen)
    wl = np.linspace(400.0, 700.0, 6)
    assert len(spectral_groups(explicit_red_dune.composition, wl)) == 1
    z_real = z_scores(explicit_red_dune, wl, rays=2000, seeds=range(1, 21))
    report(z_real)
    z = np.concatenate([z_frozen, z_real])
    report(z)
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def test_explicit_single_wavelengths_are_traced_on_their_own(explicit_red_dune):
    # share=False and a single wavelength trace the explicit medium wavelength by wavelength,
    # as before sharing (the native tracer's paths are pinned by the Rust test
    # one_wavelength_makes_the_decisions_it_made_before_spectral_sharing).
    kw = dict(rays=1000, seed=3, progress=False)
    both = sandlight.reflectance(explicit_red_dune, [500.0, 600.0], share=False, **kw)
    one = sandlight.reflectance(explicit_red_dune, [600.0], **kw)
    assert not both.shared and not one.shared
    np.testing.assert_allclose(both.values, both.counts["escaped"] / 1000)
    assert one.values[0] == both.values[1]
    assert one.counts["events"][0] == both.counts["events"][1]


@pytest.mark.parametrize(
    "medium", ["red-dune", packed(saturation=0.6), "explicit"], ids=["classic", "packed-wet", "explicit"]
)
def test_shared_results_do_not_depend_on_the_thread_count(medium, request):
    if medium == "explicit":
        medium = request.getfixturevalue("explicit_red_dune")
    wl = np.linspace(400.0, 700.0, 8)
    runs = [sandlight.reflectance(medium, wl, rays=3000, seed=5, threads=t, progress=False) for t in (1, 2, 3)]
    for r in runs[1:]:
        np.testing.assert_array_equal(r.values, runs[0].values)
        np.testing.assert_array_equal(r.covariance, runs[0].covariance)
        np.testing.assert_array_equal(r.counts["events"], runs[0].counts["events"])


def test_covariance_is_a_covariance_and_is_written():
    wl = np.array([450.0, 550.0, 650.0, 1200.0, 2400.0])
    r = sandlight.reflectance("red-dune", wl, rays=4000, seed=2, progress=False)
    c = r.covariance
    np.testing.assert_allclose(np.diag(c), r.stderr**2, rtol=1e-12)
    np.testing.assert_array_equal(c, c.T)
    assert np.linalg.eigvalsh(c).min() > -1e-12 * np.abs(c).max()
    # Wavelengths of one group are positively correlated (shared paths); groups are independent.
    same = [g for g in r.groups if len(g) > 1][0]
    assert c[same[0], same[1]] > 0
    other = [g for g in r.groups if same[0] not in g][0]
    assert c[same[0], other[0]] == 0
    ds = r.to_xarray()
    assert ds["covariance"].dims == ("wavelength", "wavelength_b") and ds.attrs["spectral_sharing"] == 1


def test_share_false_is_the_per_wavelength_engine():
    wl = [500.0, 600.0]
    r = sandlight.reflectance("red-dune", wl, rays=3000, seed=3, progress=False, share=False)
    assert not r.shared and r.counts["escaped"].dtype == np.int64
    np.testing.assert_allclose(r.values, r.counts["escaped"] / 3000)
    assert np.isnan(r.covariance[0, 1]) and r.covariance[0, 0] == r.stderr[0] ** 2
    one = sandlight.reflectance("red-dune", [600.0], rays=3000, seed=3, progress=False, share=False)
    assert one.values[0] == r.values[1]  # common random numbers, as before sharing existed


def test_media_that_cannot_share_fall_back_to_independent_runs():
    r = sandlight.reflectance(IsotropicScatterers(0.9), [500.0, 600.0], rays=500, progress=False)
    assert not r.shared


@pytest.mark.parametrize("memory", ["none", "channel", "cut", "packed"])
def test_every_path_memory_shares(memory):
    r = sandlight.reflectance("red-dune", [500.0, 600.0], rays=500, memory=memory, progress=False)
    assert r.shared and r.memory == memory and r.groups == ((0, 1),)


def test_groups_follow_the_indices_that_set_directions():
    comp = as_traceable("ottawa-quartz").composition
    wl = np.linspace(350.0, 2500.0, 67)
    groups = spectral_groups(comp, wl, 0.02)
    assert sorted(np.concatenate(groups).tolist()) == list(range(67))
    for g in groups:
        n = np.array([direction_indices(comp, lam) for lam in wl[g]])
        assert np.all(n.max(axis=0) - n.min(axis=0) <= 0.02)
    assert len(spectral_groups(comp, wl, 0.0)) == 67


@pytest.mark.parametrize(
    ("kwargs", "name"), [({"share": "yes"}, "share"), ({"dispersion_tolerance": -1}, "dispersion_tolerance")]
)
def test_bad_sharing_options_are_refused(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        sandlight.reflectance("red-dune", [500.0], rays=10, progress=False, **kwargs)
