"""The mass balance's lengths for a batch (length_scales, the predictors' physical inputs) are
compose()'s, sample by sample; the array forms of its size and shape factors are the scalar ones."""

import numpy as np
import pytest

from sandlight.physics.composition import SAND_RANGE_MM, compose, length_scales
from sandlight.physics.sizes import SizeDistribution, lognormal_mass_mean_inverse_diameter, spheroid_surface_factor
from sandlight.predictor import Domain
from sandlight.predictor.samples import sample_columns
from sandlight.sample import SandSample

#: compose() integrates the sand's E_m[1/D] on a grid, length_scales in closed form.
QUADRATURE = 1e-6


@pytest.fixture(scope="module")
def drawn():
    """Samples of every form, dry and wet, across the whole default domain (every parameter)."""
    rows = Domain.default().draw(240, seed=11, design="random")
    rows[:3] = [dict(r, saturation=0.0) for r in rows[:3]]
    return rows, length_scales(sample_columns(rows))


def test_every_form_and_water_regime_is_drawn(drawn):
    rows, _ = drawn
    assert {r["iron_oxide_form"] for r in rows} == {"coating", "mixed", "particles"}
    assert min(r["saturation"] for r in rows) == 0.0 and max(r["saturation"] for r in rows) > 0.9


def test_lengths_are_those_of_compose(drawn):
    rows, lengths = drawn
    for i, row in enumerate(rows):
        c = compose(SandSample(**row), films="uniform")
        sand = c.populations[0]
        assert sand.name == "quartz sand"
        assert lengths["mean_free_path_mm"][i] == pytest.approx(c.mean_free_path_mm, rel=QUADRATURE)
        assert lengths["coating_thickness_mm"][i] == pytest.approx(sand.coating_thickness_mm, rel=QUADRATURE)
        assert lengths["film_thickness_mm"][i] == pytest.approx(c.film_thickness_mm, rel=QUADRATURE)
        assert lengths["water_filled_probability"][i] == pytest.approx(c.water_filled_probability, abs=1e-12)
        iron_share = 1.0 - sand.core.get("quartz", 1.0)
        sauter = 6.0 / sand.surface_per_volume_per_mm
        assert lengths["core_iron_path_mm"][i] == pytest.approx(iron_share * sauter, rel=QUADRATURE, abs=1e-15)


def test_only_their_form_has_a_coating_or_iron_inside_the_grains(drawn):
    rows, lengths = drawn
    form = np.array([r["iron_oxide_form"] for r in rows])
    iron = np.array([r["iron_oxide"] for r in rows]) > 0
    assert np.all((lengths["coating_thickness_mm"] > 0) == ((form == "coating") & iron))
    assert np.all((lengths["core_iron_path_mm"] > 0) == ((form == "mixed") & iron))
    assert np.all((lengths["film_thickness_mm"] > 0) == (np.array([r["saturation"] for r in rows]) > 0))


def test_the_pendular_film_is_the_uniform_one_over_its_coverage():
    wet = SandSample.preset("red-dune").replace(saturation=0.05)
    uniform, pendular = compose(wet, films="uniform"), compose(wet, films="pendular")
    (thickness,) = length_scales(sample_columns([wet.to_dict()]))["film_thickness_mm"]
    assert pendular.film_coverage < 1.0
    assert thickness == pytest.approx(uniform.film_thickness_mm, rel=QUADRATURE)
    assert thickness / pendular.film_coverage == pytest.approx(pendular.film_thickness_mm, rel=QUADRATURE)


@pytest.mark.parametrize(("median", "spread"), [(0.06, 1.2), (0.3, 1.8), (1.5, 3.0), (0.25, 1.0)])
def test_the_closed_form_mean_inverse_diameter_is_the_integral(median, spread):
    sizes = SizeDistribution("lognormal", *SAND_RANGE_MM, median_mm=median, spread=spread)
    (closed,) = lognormal_mass_mean_inverse_diameter([median], [spread], *SAND_RANGE_MM)
    assert closed == pytest.approx(sizes.mass_mean_inverse_diameter(), rel=QUADRATURE)


def test_the_shape_factor_of_an_array_is_that_of_each_value():
    eps = np.array([1.0, 1.0 + 1e-13, 1.2, 2.0, 3.0])
    factors = spheroid_surface_factor(eps)
    assert isinstance(factors, np.ndarray) and isinstance(spheroid_surface_factor(1.2), float)
    assert factors.tolist() == [spheroid_surface_factor(float(e)) for e in eps]
    assert factors[0] == 1.0 and np.all(np.diff(factors) >= 0)
