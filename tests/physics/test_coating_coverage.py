"""SandSample.coating_coverage: the coating on a fraction f of a coated particle's surface, t/f
thick (same iron mass), drawn per surface point by the engine; the coated sand pales and loses
chroma as f falls."""

import math

import numpy as np
import pytest

from sandlight import SandSample, _native, reflectance
from sandlight.colour.lch import lch_with_chroma_error
from sandlight.errors import ParameterError
from sandlight.physics.composition import compose
from sandlight.physics.media import SandMedium

RED_DUNE = SandSample.preset("red-dune")
WAVELENGTHS_NM = np.arange(400.0, 701.0, 30.0)
RAYS = 120_000


def test_patches_carry_the_same_coating_volume():
    full = compose(RED_DUNE)
    half = compose(RED_DUNE.replace(coating_coverage=0.5))
    assert half.coating_coverage == 0.5 and full.coating_coverage == 1.0
    for a, b in zip(full.populations, half.populations):
        assert b.coating_thickness_mm == pytest.approx(2.0 * a.coating_thickness_mm, rel=1e-12)
        # coating volume per particle volume: t · f · S/V
        assert b.coating_thickness_mm * 0.5 * b.surface_per_volume_per_mm == pytest.approx(
            a.coating_thickness_mm * a.surface_per_volume_per_mm, rel=1e-12
        )


def _chroma(sample, coating_optics="uniform"):
    medium = SandMedium.from_sample(sample, coating_optics=coating_optics)
    r = reflectance(medium, WAVELENGTHS_NM, rays=RAYS, seed=5, progress=False)
    _, c, _, se = lch_with_chroma_error(r.wavelengths, r.values, r.covariance)
    return c, se


@pytest.mark.parametrize("coating_optics", ["uniform", "mie"])
def test_chroma_of_red_dune_falls_with_coverage(coating_optics):
    # Each step (1 → 0.5 → 0.25) lowers C*ab by more than 4 standard errors of the difference
    # (independent errors assumed, conservative for runs of one seed). With the default engine
    # (packed memory, calibrated k) the first step is the small one: C*ab 65.0, 62.6, 52.9
    # uniform, 64.0, 59.5, 48.0 mie at σ ≈ 0.22 (160 000 rays, measured 2026-12-06); 120 000
    # rays give σ ≈ 0.25, 4σ of a difference ≈ 1.4.
    runs = [_chroma(RED_DUNE.replace(coating_coverage=f), coating_optics) for f in (1.0, 0.5, 0.25)]
    for (c0, se0), (c1, se1) in zip(runs, runs[1:]):
        assert c0 - c1 > 4.0 * math.hypot(se0, se1), runs


def test_coverage_of_a_sand_without_coating_changes_nothing():
    # The 'mixed' form has no coating: the coverage is not met, the run is the same draw for draw.
    wet_beach = SandSample.preset("wet-beach")
    a = reflectance(wet_beach, [450.0, 600.0], rays=500, seed=2, progress=False)
    b = reflectance(wet_beach.replace(coating_coverage=0.3), [450.0, 600.0], rays=500, seed=2, progress=False)
    assert np.array_equal(a.values, b.values)


@pytest.mark.parametrize("value", [0.0, -0.1, 1.1, math.nan, "half"])
def test_out_of_domain_coverage_is_refused_with_its_name(value):
    with pytest.raises(ParameterError, match="coating_coverage"):
        SandSample(coating_coverage=value)


# One coated particle type for the binding: probabilities, size quantiles, aspect ratios, core
# n, k, α, coating n, α, thickness, free path, water n, α, film thickness, filled-pore
# probability, depth.
ONE_COATED_TYPE = ([1.0], [[0.2, 0.25, 0.3]], [1.3], [1.54], [0.0], [0.0], [1.9], [10.0], [1e-3])
PORE = (0.1, 1.333, 0.0, 0.0, 0.0, math.inf)


@pytest.mark.parametrize(
    "coverage, message",
    [
        ([1.5], r"particle_types\[0\]\.coating_coverage"),
        ([math.nan], "coating_coverage"),
        ([0.5, 0.5], "coating_coverage"),
    ],
)
def test_the_binding_refuses_a_bad_coverage_with_its_name(coverage, message):
    with pytest.raises(ParameterError, match=message):
        _native.Medium.particulate(*ONE_COATED_TYPE, *PORE, coating_coverage=coverage)
