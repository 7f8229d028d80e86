"""The transport engine against exact answers, conservation, trends and its contract.

Tolerances are 4 Monte Carlo standard errors (fixed seeds, so the tests are deterministic).
"""

import math

import numpy as np
import pytest

import sandlight
from sandlight import _native
from sandlight.errors import ParameterError
from sandlight.sample import SandSample

# --- Chandrasekhar's isotropic half-space, H computed here, independently of the package ---


def h_function(mu, omega, n=96):
    """Chandrasekhar H for isotropic scattering, from the iteration
    1/H(μ) = √(1 − ω) + (ω/2) ∫₀¹ μ' H(μ')/(μ + μ') dμ' (Chandrasekhar 1950, ch. V), damped by
    averaging successive iterates (undamped, it oscillates for ω → 1)."""
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = 0.5 * (x + 1), 0.5 * w
    h = np.ones(n)
    for _ in range(2000):
        h_new = 0.5 * (h + 1.0 / (math.sqrt(1 - omega) + 0.5 * omega * (w * x * h / (x[:, None] + x)).sum(axis=1)))
        if np.max(np.abs(h_new - h)) < 1e-13:
            break
        h = h_new
    mu = np.atleast_1d(mu)
    return 1.0 / (math.sqrt(1 - omega) + 0.5 * omega * (w * x * h / (mu[:, None] + x)).sum(axis=1))


def test_h_function_reference_values():
    # Conservative case: H(1) = 2.9078 (Chandrasekhar 1950, Table XI); and the moment identity
    # ∫₀¹ H dμ = 2(1 − √(1 − ω))/ω.
    assert h_function(1.0, 1.0)[0] == pytest.approx(2.9078, abs=2e-4)
    x, w = np.polynomial.legendre.leggauss(64)
    for omega in (0.3, 0.9):
        h0 = (0.5 * w * h_function(0.5 * (x + 1), omega)).sum()
        assert h0 == pytest.approx(2 * (1 - math.sqrt(1 - omega)) / omega, rel=1e-6)


@pytest.mark.parametrize("omega", [0.3, 0.9, 0.99])
@pytest.mark.parametrize("incidence_deg", [0.0, 60.0])
def test_isotropic_halfspace_matches_chandrasekhar(omega, incidence_deg):
    mu0 = math.cos(math.radians(incidence_deg))
    exact = 1.0 - h_function(mu0, omega)[0] * math.sqrt(1.0 - omega)
    rho, se = sandlight.isotropic_halfspace(omega, rays=200_000, incidence_deg=incidence_deg, seed=1)
    assert abs(rho - exact) < 4 * se, (rho, se, exact)


def test_conservative_isotropic_halfspace_reflects_everything():
    rho, se = sandlight.isotropic_halfspace(1.0, rays=2000, seed=2, max_events=10**9)
    assert rho == 1.0 and se == 0.0


# --- Fresnel at the first surface of a sphere ---


def fresnel_dielectric(n1, n2, cos_i):
    sin_t = n1 / n2 * np.sqrt(1 - cos_i**2)
    cos_t = np.sqrt(1 - sin_t**2)
    rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t)
    rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t)
    return 0.5 * (rs**2 + rp**2)


def one_type_medium(
    n=1.5, k=0.0, alpha=0.0, aspect=1.0, coating=(1.0, 0.0, 0.0), film=0.0, filled=0.0, water_alpha=0.0, depth=math.inf
):
    cn, ca, ct = coating
    return _native.Medium.particulate(
        [1.0], [[0.25]], [aspect], [n], [k], [alpha], [cn], [ca], [ct], 0.2, 1.333, water_alpha, film, filled, depth
    )


def test_first_surface_reflection_of_a_sphere_is_hemispherical_fresnel():
    # An opaque core absorbs everything refracted; with at most one particle event per ray, a
    # ray reflected at the first surface either escapes or is stopped at its second event.
    medium = one_type_medium(n=1.5, alpha=1e9)
    n = 200_000
    launched, escaped, absorbed, transmitted, capped, _ = medium.dhr(0.0, 3, 0, 0, n, 1, 10_000)
    assert launched == n and transmitted == 0
    frac = (escaped + capped) / n
    x, w = np.polynomial.legendre.leggauss(200)
    mu = 0.5 * (x + 1)
    expected = (0.5 * w * 2 * fresnel_dielectric(1.0, 1.5, mu) * mu).sum()  # 2∫R(μ)μdμ ≈ 0.092
    assert expected == pytest.approx(0.092, abs=2e-3)
    se = math.sqrt(expected * (1 - expected) / n)
    assert abs(frac - expected) < 4 * se


# --- Energy conservation ---


@pytest.mark.parametrize(
    "aspect,coating,film,filled",
    [
        (1.0, (1.0, 0.0, 0.0), 0.0, 0.0),
        (2.5, (1.9, 0.0, 0.0005), 0.001, 0.0),
        (1.4, (1.0, 0.0, 0.0), 0.002, 0.7),
    ],
)
def test_no_absorption_reflects_everything(aspect, coating, film, filled):
    # Without absorption every ray returns, but the number of events before it does is
    # heavy-tailed (P(N > n) ~ n^(-1/2) for a random walk near a boundary), so the run is kept
    # small and the caps high (total internal reflection can also keep a ray inside a prolate
    # grain for more than 10⁴ reflections).
    medium = one_type_medium(n=1.544, aspect=aspect, coating=coating, film=film, filled=filled)
    launched, escaped, absorbed, transmitted, capped, _ = medium.dhr(30.0, 5, 0, 0, 100, 10**8, 10**7)
    assert (escaped, absorbed, transmitted, capped) == (launched, 0, 0, 0)


def test_no_absorption_in_a_finite_slab_conserves_rays():
    medium = one_type_medium(n=1.544, aspect=1.4, depth=2.0)
    launched, escaped, absorbed, transmitted, capped, _ = medium.dhr(0.0, 5, 0, 0, 5000, 10**9, 10_000)
    assert absorbed == 0 and capped == 0 and escaped + transmitted == launched and transmitted > 0


# --- Trends with real optical constants ---


def _dhr(sample, wavelengths, rays=20_000, seed=7):
    return sandlight.reflectance(sample, wavelengths, rays=rays, seed=seed, progress=False)


def _clearly_less(a, b, i=slice(None)):
    """a < b by more than 4 combined standard errors, element-wise."""
    return np.all(a.values[i] + 4 * np.hypot(a.stderr[i], b.stderr[i]) < b.values[i])


def test_more_iron_oxide_is_darker_at_450nm():
    base = SandSample(iron_oxide=0.002)
    assert _clearly_less(_dhr(base.replace(iron_oxide=0.02), [450]), _dhr(base, [450]))


def test_wet_sand_is_darker_than_dry_at_every_visible_wavelength():
    # Light-coloured sand (0.2 wt% iron oxide, reflectance ≥ 0.1): wetting darkens it. Sand darker
    # than the ~2 % that the flat water surfaces of filled pores reflect specularly can come out
    # brighter when wet (the default sample at 400 nm: 0.018 dry, 0.023 saturated), so the
    # claim is not made for it.
    dry = SandSample(saturation=0.0, iron_oxide=0.002)
    wl = np.arange(400, 701, 50)
    assert _clearly_less(_dhr(dry.replace(saturation=1.0), wl), _dhr(dry, wl))


def test_finer_grains_are_brighter():
    coarse = SandSample(grain_size=1.0, sand=1.0, silt=0.0, clay=0.0)
    assert _clearly_less(_dhr(coarse, [550, 650]), _dhr(coarse.replace(grain_size=0.1), [550, 650]))


def _hue_deg(wl, values):
    from sandlight.colour import spectrum_to_xyz, xyz_to_lab

    lab = xyz_to_lab(spectrum_to_xyz(wl, values))
    return math.degrees(math.atan2(lab[2], lab[1]))


def test_hematite_is_redder_than_goethite():
    # "Redder": a smaller CIELAB hue angle (toward red). Its standard error is propagated from
    # the per-band errors by finite differences.
    wl = np.arange(400, 701, 20)
    hues, ses = [], []
    for ratio in (1.0, 0.0):
        r = _dhr(SandSample(hematite_ratio=ratio), wl)
        hue = _hue_deg(wl, r.values)
        grad = [(_hue_deg(wl, r.values + 1e-4 * np.eye(wl.size)[i]) - hue) / 1e-4 for i in range(wl.size)]
        hues.append(hue)
        ses.append(float(np.sqrt(np.sum((np.array(grad) * r.stderr) ** 2))))
    assert hues[1] - hues[0] > 4 * math.hypot(*ses), (hues, ses)


# --- Determinism, bookkeeping, input checking ---


def test_same_seed_is_bit_identical_for_any_thread_count_and_batching():
    s = SandSample.preset("red-dune")
    one = sandlight.reflectance(s, [450, 650], rays=6000, seed=11, threads=1, progress=False)
    two = sandlight.reflectance(s, [450, 650], rays=6000, seed=11, threads=2, progress=False)
    assert all(np.array_equal(one.counts[k], two.counts[k]) for k in one.counts)
    other = sandlight.reflectance(s, [450, 650], rays=6000, seed=12, threads=2, progress=False)
    assert not np.array_equal(one.counts["escaped"], other.counts["escaped"])


def test_counts_add_up_and_stats_are_reported():
    r = _dhr(SandSample.preset("wet-beach"), [1250, 1450], rays=3000)
    c = r.counts
    assert np.all(c["escaped"] + c["absorbed"] + c["transmitted"] + c["capped"] == c["launched"])
    assert np.all(r.mean_events_per_ray > 0) and np.all(r.capped == 0)
    assert np.allclose(r.stderr, np.sqrt(r.values * (1 - r.values) / 3000))
    # Water's 1450 nm band darkens wet sand relative to the 1250 nm window.
    assert r.values[1] < r.values[0]


def test_event_cap_is_counted_not_dropped():
    r = sandlight.reflectance(SandSample.preset("ottawa-quartz"), [550], rays=500, max_events=3, progress=False)
    assert r.capped[0] > 0
    assert r.counts["escaped"][0] + r.counts["absorbed"][0] + r.capped[0] == 500


@pytest.mark.parametrize(
    "kwargs,name",
    [
        (dict(wavelengths_nm=[300]), "wavelengths_nm"),
        (dict(wavelengths_nm=[float("nan")]), "wavelengths_nm"),
        (dict(wavelengths_nm=[]), "wavelengths_nm"),
        (dict(rays=0), "rays"),
        (dict(rays=1.5), "rays"),
        (dict(rays="many"), "rays"),
        (dict(incidence_deg=90), "incidence_deg"),
        (dict(incidence_deg=-1), "incidence_deg"),
        (dict(seed=-1), "seed"),
        (dict(seed=1.5), "seed"),
        (dict(threads=0), "threads"),
    ],
)
def test_invalid_run_arguments_name_the_parameter(kwargs, name):
    args = dict(wavelengths_nm=[550], rays=10)
    args.update(kwargs)
    with pytest.raises(ParameterError, match=name):
        sandlight.reflectance(SandSample(), args.pop("wavelengths_nm"), progress=False, **args)


def test_invalid_sample_argument():
    with pytest.raises(ParameterError, match="sample"):
        sandlight.reflectance({"iron_oxide": 0.01}, [550], rays=10)


def test_native_medium_rejects_bad_values_with_parameter_errors():
    with pytest.raises(ParameterError, match="albedo"):
        _native.Medium.isotropic(1.5)
    with pytest.raises(ParameterError, match="aspect_ratio"):
        one_type_medium(aspect=0.5)
    with pytest.raises(ParameterError, match="size_quantiles_mm"):
        _native.Medium.particulate(
            [1.0], [[-1.0]], [1.0], [1.5], [0.0], [0.0], [1.0], [0.0], [0.0], 0.2, 1.333, 0.0, 0.0, 0.0, math.inf
        )


def test_result_files(tmp_path):
    import xarray as xr

    r = _dhr(SandSample(), [450, 550], rays=500)
    r.to_netcdf(tmp_path / "r.nc")
    ds = xr.open_dataset(tmp_path / "r.nc", engine="h5netcdf")
    assert np.allclose(ds["reflectance"].values, r.values) and ds["wavelength"].attrs["units"] == "nm"
    assert ds.attrs["rays"] == 500
    r.to_csv(tmp_path / "r.csv")
    lines = (tmp_path / "r.csv").read_text().splitlines()
    comments = [line for line in lines if line.startswith("# ")]  # the metadata, then the header
    assert "# rays: 500" in comments and lines[len(comments)].startswith("wavelength_nm,reflectance,")
    table = np.loadtxt(tmp_path / "r.csv", delimiter=",", skiprows=len(comments) + 1)
    assert np.allclose(table[:, 1], r.values)
    r.plot(tmp_path / "r.png")
    assert (tmp_path / "r.png").stat().st_size > 1000
