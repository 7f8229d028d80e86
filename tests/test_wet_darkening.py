"""How water darkens sand in the engine (docs/wet-sand.md): grey when the grains are grey, deeper
water bands with more water, in both path-memory models.

Tolerances are 4 Monte Carlo standard errors of the compared quantities (fixed seeds). The
wet/dry ratio's error is propagated as if dry and wet were independent, an upper bound: both
runs share their seed, so their noise is correlated.
"""

import dataclasses
import warnings

import numpy as np
import pytest

import sandlight
from sandlight.optics import complex_index
from sandlight.physics.composition import compose
from sandlight.physics.media import SandMedium
from sandlight.physics.medium import absorption_per_mm
from sandlight.sample import SandSample

#: A grey host: quartz with the absorption coefficient α = 2 mm⁻¹ at every wavelength (k ∝ λ).
GREY_ALPHA_PER_MM = 2.0


def grey_host(material, wavelength_nm):
    n = complex(complex_index(material, wavelength_nm))
    if material == "quartz":
        n += 1j * GREY_ALPHA_PER_MM / absorption_per_mm(1.0, wavelength_nm)
    return n


def _ratio(memory, saturation, wl, rays, sample=None, seed=5):
    """wet/dry ratio and its standard error at ``wl`` for an uncoated grey-host sand."""
    sample = sample or SandSample(iron_oxide=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the surface-layer models warn on filled pores
        runs = [
            sandlight.reflectance(
                SandMedium.from_sample(sample.replace(saturation=s), memory, optical_constants=grey_host),
                wl,
                rays=rays,
                seed=seed,
                progress=False,
                share=False,
            )
            for s in (0.0, saturation)
        ]
    dry, wet = runs
    r = wet.values / dry.values
    return r, r * np.hypot(dry.stderr / dry.values, wet.stderr / wet.values)


@pytest.mark.parametrize("memory", ["none", "packed"])
def test_grey_sand_darkens_grey(memory):
    # With the same absorption coefficient at every wavelength and water transparent (450 and
    # 800 nm: water α < 3e-3 mm⁻¹), only the small dispersion of quartz and water differs between
    # the two wavelengths, so the wet/dry ratio must be the same: the engine adds no hue of its own.
    r, se = _ratio(memory, 0.6, [450.0, 800.0], rays=20_000)
    assert r[0] < 0.9 and r[1] < 0.9, r  # it does darken
    assert abs(r[0] - r[1]) < 4 * np.hypot(*se), (r, se)


@pytest.mark.parametrize("memory", ["none", "packed"])
def test_water_band_deepens_with_saturation(memory):
    # At 1450 nm water absorbs (α ≈ 2.6 mm⁻¹); at 1300 nm it hardly does. The band's relative
    # depth, ratio(1450)/ratio(1300), falls as the pores fill.
    wl = [1300.0, 1450.0]
    depth = []
    for s in (0.3, 0.8):
        r, se = _ratio(memory, s, wl, rays=10_000)
        depth.append((r[1] / r[0], (r[1] / r[0]) * np.hypot(se[0] / r[0], se[1] / r[1])))
    (d_low, se_low), (d_high, se_high) = depth
    assert d_high + 4 * np.hypot(se_low, se_high) < d_low, depth


def test_pendular_rings_darken_a_coated_sand_less_in_the_blue_than_a_uniform_film():
    # The default sample (1 % iron oxide as a coating) with films only (S = 0.1 < S_f). Under
    # water the coating's outer interface reflects less, so more light crosses the absorbing
    # coating, which matters where it absorbs (450 nm). Pendular rings wet only part of the
    # surface (film_coverage ≈ 0.52 here), a uniform film of the same water all of it: the
    # rings must darken the blue less.
    wl = [450.0]
    dry = compose(SandSample())
    rings = compose(SandSample(saturation=0.1))
    uniform = dataclasses.replace(
        rings, film_coverage=1.0, film_thickness_mm=rings.film_thickness_mm * rings.film_coverage
    )
    assert 0.3 < rings.film_coverage < 0.7
    runs = [
        sandlight.reflectance(SandMedium(c, "none"), wl, rays=40_000, seed=8, progress=False, share=False)
        for c in (dry, rings, uniform)
    ]
    v, se = np.array([r.values[0] for r in runs]), np.array([r.stderr[0] for r in runs])
    assert v[1] < v[0] - 4 * np.hypot(se[0], se[1])  # the rings darken
    assert v[2] + 4 * np.hypot(se[1], se[2]) < v[1], (v, se)  # the uniform film darkens more
