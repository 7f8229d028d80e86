"""Explicit reference geometry and near-surface path memory (issue 9, docs/geometry.md).

Needs the native extension built from this tree (``_native.Packing``).
"""

import math

import numpy as np
import pytest

from sandlight import _native
from sandlight.errors import ParameterError
from sandlight.physics.packing import generate_packing, grain_medium, grains_with_fines

pytestmark = pytest.mark.skipif(not hasattr(_native, "Packing"), reason="native extension without explicit geometry")

D_MM = 0.25
POROSITY = 0.40


@pytest.fixture(scope="module")
def spheres():
    """Monodisperse spheres, d = 0.25 mm, φ = 0.40, in a 2 mm × 2 mm × 2 mm periodic box."""
    return generate_packing(
        grain_medium([D_MM], porosity=POROSITY), reference_mm=D_MM, lateral_mm=2.0, depth_mm=2.0, seed=7
    )


def test_sphere_packing_reaches_the_porosity_without_overlap(spheres):
    assert spheres.packing_fraction == pytest.approx(1 - POROSITY, abs=1e-9)
    assert spheres.sample_porosity == pytest.approx(POROSITY, abs=1e-9)
    # Point sampling of the actual pore space (sd √(φ(1 − φ)/N) ≈ 0.0015).
    empty, multiple = spheres.point_statistics(100_000, 3)
    assert empty == pytest.approx(POROSITY, abs=0.01)
    # Exact pair check with the minimum image: no overlap beyond the tolerance 1e-3 d.
    centres, diameters = spheres.particles()
    period = np.array(spheres.period_mm)
    worst = 0.0
    for i in range(len(centres) - 1):
        r = centres[i + 1 :] - centres[i]
        r -= period * np.round(r / period)
        worst = max(worst, float(np.max(0.5 * (diameters[i] + diameters[i + 1 :]) - np.linalg.norm(r, axis=1))) / D_MM)
    assert worst <= 1e-3
    assert spheres.max_overlap <= 1e-3


def test_spheroid_packing_porosity_and_true_overlap():
    pk = generate_packing(
        grain_medium([D_MM], aspect_ratio=1.4, porosity=POROSITY),
        reference_mm=D_MM,
        lateral_mm=1.6,
        depth_mm=1.6,
        seed=2,
    )
    empty, multiple = pk.point_statistics(100_000, 4)
    assert empty == pytest.approx(POROSITY, abs=0.01)
    # The radial contact rule leaves off-centre-line overlaps: below 1 % of the volume.
    assert multiple < 0.01


def test_mean_pore_chord_matches_the_exponential_law(spheres):
    chords = spheres.pore_chords(3000, 10, 5)
    expected = 2.0 / 3.0 * D_MM * POROSITY / (1 - POROSITY)
    assert chords.mean() == pytest.approx(expected, rel=0.03)
    # Exponential chords: standard deviation equal to the mean.
    assert chords.std() / chords.mean() == pytest.approx(1.0, abs=0.08)


def _dhr(medium, rays, seed=11):
    c = medium.dhr(0.0, seed, 0, 0, rays, 10_000_000, 10_000, None)
    rho = c[1] / c[0]
    return rho, math.sqrt(rho * (1 - rho) / c[0])


def _against_explicit(spheres, alpha, memory, baseline, rays=200_000):
    """(reference, its error, `memory`, its error, `baseline`) for the spheres at α (mm⁻¹)."""
    ref, ref_se = _dhr(grain_medium([D_MM], alpha_per_mm=alpha).explicit(spheres), rays)
    value, value_se = _dhr(grain_medium([D_MM], alpha_per_mm=alpha, memory=memory), rays)
    base, _ = _dhr(grain_medium([D_MM], alpha_per_mm=alpha, memory=baseline), rays)
    return ref, ref_se, value, value_se, base


def test_path_memory_meets_the_target_on_dark_grains(spheres):
    # α = 50 cm⁻¹ = 5 mm⁻¹: the case where the classic model is 30 % too dark. Target: within
    # 3 % relative or 0.002 absolute of the explicit reference (issue 9).
    ref, ref_se, cut, cut_se, classic = _against_explicit(spheres, 5.0, "cut", "none")
    target = max(0.03 * ref, 0.002)
    assert abs(cut - ref) < target, (cut, ref)
    assert abs(classic - ref) > target + 3 * math.hypot(ref_se, cut_se), (classic, ref)


def test_neighbour_memory_meets_the_target_on_spheres(spheres):
    # α = 5 cm⁻¹: `cut` is 3.5 % too bright here (light diffuses less far on the fly than among
    # packed grains); `packed` places each grain met after leaving one by the packing's pair
    # correlation (docs/geometry.md). At scale: explicit 0.2183, cut 0.2261, packed 0.2167.
    ref, ref_se, packed, packed_se, cut = _against_explicit(spheres, 0.5, "packed", "cut")
    assert abs(packed - ref) < max(0.03 * ref, 0.002), (packed, ref)
    assert abs(cut - ref) > abs(packed - ref) + 3 * math.hypot(ref_se, packed_se), (cut, packed, ref)


def test_neighbour_memory_applies_to_spheres_only():
    # The pair correlation is that of sphere packings: spheroids are traced as with `cut`, ray
    # for ray; spheres are not.
    def counts(aspect_ratio, memory):
        return grain_medium([D_MM], aspect_ratio=aspect_ratio, alpha_per_mm=0.5, memory=memory).dhr(
            0.0, 5, 0, 0, 20_000, 10**7, 10**4, None
        )

    assert counts(1.4, "packed") == counts(1.4, "cut")
    assert counts(1.0, "packed") != counts(1.0, "cut")


def _grains_with_fines(memory="none"):
    """Grains (d = 0.25 mm, α = 5 cm⁻¹) with fines (2 µm, α = 50 cm⁻¹) that make 90 % of the
    encounters: light is scattered many times inside each pore."""
    return grains_with_fines(
        alpha_per_mm=0.5, fines_alpha_per_mm=5.0, diameter_mm=D_MM, porosity=POROSITY, memory=memory
    )


def test_path_memory_meets_the_target_with_fines():
    # The classic model is 10 % too bright here: each wall encounter of light diffusing among
    # the fines is a fresh grain. `cut` remembers the pore's walls (docs/geometry.md).
    pk = generate_packing(_grains_with_fines(), reference_mm=D_MM, lateral_mm=2.0, depth_mm=2.0, seed=7)
    rays = 100_000
    ref, ref_se = _dhr(_grains_with_fines().explicit(pk), rays)
    cut, cut_se = _dhr(_grains_with_fines("cut"), rays)
    classic, _ = _dhr(_grains_with_fines("none"), rays)
    target = max(0.03 * ref, 0.002)
    assert abs(cut - ref) < target, (cut, ref)
    assert abs(classic - ref) > target + 3 * math.hypot(ref_se, cut_se), (classic, ref)


def test_explicit_reflectance_through_the_public_api():
    import sandlight
    from sandlight.physics.composition import compose
    from sandlight.physics.medium import native_medium
    from sandlight.sample import SandSample

    sample = SandSample(
        grain_size=0.4,
        grain_size_spread=1.0,
        aspect_ratio=1.0,
        sand=1.0,
        silt=0.0,
        clay=0.0,
        iron_oxide=0.01,
        porosity=0.4,
    )
    comp = compose(sample)
    pk = generate_packing(native_medium(comp, 550.0), reference_mm=0.4, lateral_mm=2.5, depth_mm=2.5, seed=1)
    kw = dict(rays=20_000, seed=3, progress=False)
    explicit = sandlight.reflectance(sample, [450.0, 650.0], geometry="explicit", packing=pk, **kw)
    fast = sandlight.reflectance(sample, [450.0, 650.0], **kw)
    classic = sandlight.reflectance(sample, [450.0, 650.0], memory="none", **kw)
    assert explicit.geometry == "explicit" and fast.geometry == "on-the-fly" and fast.memory == "packed"
    assert (explicit.counts["transmitted"] == 0).all()  # semi-infinite: nothing leaves the bottom
    # Same sand, different geometry: the iron-oxide spectrum (darker in the blue) in all three;
    # where the sand is dark the explicit surface returns more light than the classic model
    # (issue 9's finding: 0.030 against 0.014 at 450 nm), and the default path memory, made to
    # follow the packing, agrees with it within 4 standard errors (0.029).
    for r in (explicit, fast, classic):
        assert r.values[0] < r.values[1]
    assert explicit.values[0] > classic.values[0] + 4 * math.hypot(explicit.stderr[0], classic.stderr[0])
    np.testing.assert_array_less(abs(explicit.values - fast.values), 4 * np.hypot(explicit.stderr, fast.stderr))


def test_default_box_grows_to_hold_the_largest_grains():
    # Grains of 0.3-1.0 mm with a 0.12 mm reference: the 16 x 32 reference-grain box (1.92 mm
    # across) cannot hold three 1 mm grains; the default grows, a box that is given does not.
    medium = grain_medium(np.linspace(0.3, 1.0, 8))
    pk = generate_packing(medium, reference_mm=0.12, seed=3)
    assert pk.period_mm[0] == pytest.approx(16 * 0.12 * 1.5**2) and pk.period_mm[0] >= 3 * 1.0
    with pytest.raises(ParameterError, match="lateral_mm/depth_mm"):
        generate_packing(medium, reference_mm=0.12, lateral_mm=1.92, depth_mm=3.84, seed=3)


def test_surface_layer_models_warn_on_wet_sand():
    import dataclasses
    import warnings

    import sandlight
    from sandlight.sample import SandSample

    wet = dataclasses.replace(SandSample.preset("red-dune"), saturation=0.5)
    with pytest.warns(UserWarning, match="Wet sand"):
        sandlight.reflectance(wet, [550.0], rays=100, memory="cut", progress=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sandlight.reflectance("red-dune", [550.0], rays=100, memory="cut", progress=False)
        sandlight.reflectance(wet, [550.0], rays=100, progress=False)


def test_bad_geometry_and_memory_are_rejected():
    import sandlight

    with pytest.raises(ParameterError, match="geometry"):
        sandlight.reflectance("red-dune", [550.0], rays=10, geometry="voxels", progress=False)
    with pytest.raises(ParameterError, match="memory"):
        sandlight.reflectance("red-dune", [550.0], rays=10, memory="long", progress=False)
    with pytest.raises(ParameterError, match="memory"):
        sandlight.reflectance("red-dune", [550.0], rays=10, geometry="explicit", memory="cut", progress=False)
    with pytest.raises(ParameterError, match="memory"):
        grain_medium([D_MM], memory="forever")
    for bad in (0.0, -1.0, math.nan, "thick"):
        with pytest.raises(ParameterError, match="depth_mm"):
            grain_medium([D_MM], depth_mm=bad)


def test_slabs_are_measured_from_the_same_plane_on_the_fly_and_explicit(spheres):
    """A non-absorbing slab 1 mm thick below the cut plane: every ray escapes or is transmitted,
    and `cut` (depth from its cut plane) transmits like the explicit slab cut off 1 mm below the
    plane of centres. Measured at scale (docs/geometry.md, diagnostics): 1.1 % apart; a slab
    thicker by one grain radius transmits 5 % less."""
    rays = 20_000
    t = {}
    for label, medium in (
        ("explicit", grain_medium([D_MM]).explicit(spheres, 1.0)),
        ("cut", grain_medium([D_MM], memory="cut", depth_mm=1.0)),
    ):
        launched, escaped, absorbed, transmitted, capped, _ = medium.dhr(0.0, 3, 0, 0, rays, 10**7, 10**4, None)
        assert absorbed == 0 and capped == 0 and escaped + transmitted == launched
        t[label] = transmitted / launched
    se = math.sqrt(2 * t["explicit"] * (1 - t["explicit"]) / rays)
    assert abs(t["cut"] - t["explicit"]) <= 0.03 * t["explicit"] + 4 * se


def test_goniophotometer_traces_the_explicit_geometry():
    import sandlight
    from sandlight.gonio.measure import fixed_incidence
    from sandlight.physics.composition import compose
    from sandlight.physics.medium import native_medium
    from sandlight.sample import SandSample

    sample = SandSample(
        grain_size=0.4,
        grain_size_spread=1.0,
        aspect_ratio=1.0,
        sand=1.0,
        silt=0.0,
        clay=0.0,
        iron_oxide=0.002,
        porosity=0.4,
    )
    pk = generate_packing(native_medium(compose(sample), 550.0), reference_mm=0.4, lateral_mm=2.5, depth_mm=2.5, seed=1)
    g = fixed_incidence(
        sample,
        550.0,
        incidence_deg=0.0,
        rays=5000,
        stacks=6,
        slices=8,
        seed=4,
        geometry="explicit",
        packing=pk,
        progress=False,
    )
    r = sandlight.reflectance(sample, [550.0], rays=5000, seed=4, geometry="explicit", packing=pk, progress=False)
    # Normal incidence: the same rays with the same random streams, tallied two ways.
    assert g.reflectance == r.values[0]
    with pytest.raises(ParameterError, match="geometry"):
        fixed_incidence(sample, 550.0, incidence_deg=0.0, rays=10, geometry="sphere-pack", progress=False)
