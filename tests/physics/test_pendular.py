"""Pendular rings: the toroidal ring volume, the wetted fraction, and the films they give."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from sandlight.errors import ParameterError
from sandlight.physics.composition import compose
from sandlight.physics.pendular import CONTACTS, film_coverage, ring_saturation, ring_volume, wetted_fraction
from sandlight.sample import SandSample


def toroidal_ring_volume(beta, r=1.0):
    """Volume between two touching spheres (centres at x = ±r) and a circular meniscus tangent
    to both at half-angle β, integrated numerically: the arc's centre is at (0, r tan β), its
    radius r(sec β − 1); V = ∫ π (r_meniscus² − r_sphere²) dx over the ring."""
    rho, r_c = r * (1 / math.cos(beta) - 1), r * math.tan(beta)
    x_t = r * (1 - math.cos(beta))

    def slab(x):
        r_m = r_c - math.sqrt(rho**2 - x**2)
        r_s2 = r**2 - (r - abs(x)) ** 2
        return math.pi * (r_m**2 - r_s2)

    return 2 * quad(slab, 0.0, x_t, epsabs=1e-13, epsrel=1e-11)[0]


@pytest.mark.parametrize("beta_deg", [5.0, 20.0, 38.0, 55.0])
def test_ring_volume_is_the_toroidal_ring(beta_deg):
    beta = math.radians(beta_deg)
    assert ring_volume(beta) == pytest.approx(toroidal_ring_volume(beta), rel=1e-8)


def test_coverage_rises_with_saturation_from_zero_to_one():
    s = np.linspace(0.0, 0.6, 61)
    f = np.array([film_coverage(x, 0.4) for x in s])
    assert f[0] == 0.0 and f[-1] == 1.0
    assert np.all(np.diff(f) >= 0) and np.all((f >= 0) & (f <= 1))
    # Small rings: V ∝ β⁴ and f ∝ β², so f ∝ √S.
    assert film_coverage(4e-10, 0.4) / film_coverage(1e-10, 0.4) == pytest.approx(2.0, rel=0.005)


def test_coverage_inverts_the_ring_geometry():
    beta = math.radians(30.0)
    s = ring_saturation(beta, 0.4)
    assert film_coverage(s, 0.4) == pytest.approx(wetted_fraction(beta), rel=1e-9)
    assert wetted_fraction(beta) == pytest.approx(CONTACTS * (1 - math.cos(beta)) / 2)


@pytest.mark.parametrize("saturation", [0.0, 0.05, 0.15, 0.6])
def test_films_hold_the_pendular_water(saturation):
    # Water volume of the films per pore chord: coverage × thickness = min(S, S_f) ℓ/4
    # (docs/model.md §2.5), whatever the coverage.
    sample = SandSample(saturation=saturation)
    comp = compose(sample, "pendular")
    s_film = min(saturation, sample.film_saturation)
    assert comp.film_coverage * comp.film_thickness_mm == pytest.approx(s_film * comp.mean_free_path_mm / 4)
    assert comp.film_coverage == (1.0 if saturation == 0 else pytest.approx(film_coverage(s_film, 0.4)))


@pytest.mark.parametrize("saturation", [0.05, 0.3])
def test_uniform_films_hold_the_same_water_on_every_particle(saturation):
    # The model before issue 17: the film covers every particle (coverage 1); the default is the
    # pendular rings, with the same water.
    sample = SandSample(saturation=saturation, porosity=0.4)
    uniform, rings = compose(sample, "uniform"), compose(sample)
    assert uniform.film_coverage == 1.0 and rings.film_coverage < 1.0
    assert uniform.film_thickness_mm == pytest.approx(rings.film_coverage * rings.film_thickness_mm, rel=1e-12)
    assert uniform.water_filled_probability == rings.water_filled_probability


def test_an_unknown_film_model_is_refused_with_its_name():
    with pytest.raises(ParameterError, match="films"):
        compose(SandSample(saturation=0.1), "rings")
