"""The powder forward model (``sandlight.fit(..., forward='powder')``)."""

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.physics.powder import Powder
from sandlight.retrieval.powder_forward import PowderForward, PowderSpace

RAYS = 2000
WINDOW = np.arange(600.0, 1001.0, 25.0)
NOISE = 0.005


@pytest.fixture(scope="module")
def powder_spectrum():
    """A 20 µm hematite powder: engine spectrum at 40000 rays (another seed than the fit's; its
    Monte Carlo error, about 0.0025, below the noise) plus Gaussian noise of σ = NOISE, fixed seeds."""
    truth = sandlight.reflectance(Powder("hematite", 20.0), WINDOW, rays=40_000, seed=102, share=False, progress=False)
    return WINDOW, truth.values + NOISE * np.random.default_rng(2).standard_normal(WINDOW.size)


def powder_fit(spectrum, free, fixed=None, **kw):
    return sandlight.fit(
        spectrum, free, fixed, forward="powder", material="hematite", rays=RAYS, wavelengths=WINDOW, threads=1, **kw
    )


def test_powder_fit_recovers_the_diameter_within_its_interval(powder_spectrum):
    result = powder_fit(powder_spectrum, ["diameter_um"], noise=NOISE)
    # the 99 % interval: the 95 % intervals of powder fits cover the truth in 75 % of synthetic
    # fits (the common-random-number objective is rough in d; docs/retrieval.md)
    lo, hi = result.interval("diameter_um", level=0.99)
    assert lo < 20.0 < hi
    assert abs(np.log10(result.estimate["diameter_um"] / 20.0)) < 0.05
    # informative: the 95 % interval is within a factor 1.3 of the estimate (fitted in log d)
    lo, hi = result.interval("diameter_um")
    assert hi / lo < 1.3**2
    assert isinstance(result.sample, Powder) and result.sample.material == "hematite"
    assert result.sample.sizes_um[0] == pytest.approx(result.estimate["diameter_um"])
    assert "hematite powder" in result.model and "[powder]" in result.to_toml()


def test_the_diameter_is_fitted_in_log_and_the_scale_multiplies():
    space = PowderSpace.build(["diameter_um", "scale"], {"porosity": 0.5}, "hematite")
    np.testing.assert_allclose(space.low, [0.0, 0.25])
    np.testing.assert_allclose(space.high, [3.0, 4.0])
    assert space.values(np.array([1.0, 2.0])) == {"diameter_um": 10.0, "scale": 2.0}
    assert space.sample(np.array([1.0, 2.0])).porosity == 0.5
    forward = PowderForward(space, [800.0, 900.0], rays=RAYS, seed=3, threads=1)
    once, twice = forward.predict(np.array([[1.0, 1.0], [1.0, 2.0]]))
    np.testing.assert_allclose(twice, 2 * once)  # common random numbers: the same spectrum, doubled


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"material": "unobtainium"}, "material"),
        ({"free": ["scale"], "fixed": {"diameter_um": 5000.0}}, "diameter_um"),
        ({"free": ["scale"], "fixed": {"diameter_um": 0.1}}, "diameter_um"),
        ({"free": ["grain_size"]}, "free"),
        ({"free": ["diameter_um", "diameter_um"]}, "free"),
        ({"fixed": {"iron_oxide": 0.02}}, "fixed"),
        ({"fixed": {"scattering_per_mm": -1.0}}, "scattering_per_mm"),
        ({"fixed": {"scale": 2.0}, "free": ["diameter_um", "scale"]}, "fixed"),
        ({"method": "bank"}, "method"),
        ({"forward": "dust"}, "forward"),
        ({"memory": "full"}, "memory"),
    ],
)
def test_bad_powder_input_names_the_parameter(powder_spectrum, kwargs, name):
    args = {"free": ["diameter_um"], "fixed": None, "material": "hematite", "forward": "powder"} | kwargs
    with pytest.raises(ParameterError) as err:
        sandlight.fit(powder_spectrum, args.pop("free"), args.pop("fixed"), rays=RAYS, wavelengths=WINDOW, **args)
    assert err.value.name == name


def test_a_sand_fit_refuses_a_material(dry_spectrum):
    with pytest.raises(ParameterError) as err:
        sandlight.fit(dry_spectrum, ["iron_oxide"], material="hematite")
    assert err.value.name == "material"
    with pytest.raises(ParameterError) as err:
        sandlight.fit(dry_spectrum, ["iron_oxide"], memory="packed")
    assert err.value.name == "memory"


def test_the_powder_is_traced_with_the_memory_asked_for():
    classic = PowderSpace.build(["diameter_um"], None, "hematite")
    packed = PowderSpace.build(["diameter_um"], None, "hematite", "packed")
    x = np.array([2.0])
    assert classic.sample(x).memory == "none" and packed.sample(x).memory == "packed"
    assert "memory 'packed'" in PowderForward(packed, WINDOW, rays=RAYS, seed=3, threads=1).describe()


def test_the_grains_scattering_is_a_powder_parameter():
    # Clear grains unless fixed or fitted (docs/model.md §2.4 item 9); linear in mm⁻¹.
    assert PowderSpace.build(["diameter_um"], None, "hematite").sample(np.array([2.0])).scattering_per_mm == 0.0
    fixed = PowderSpace.build(["diameter_um"], {"scattering_per_mm": 30.0}, "hematite")
    assert fixed.sample(np.array([2.0])).scattering_per_mm == 30.0
    free = PowderSpace.build(["diameter_um", "scattering_per_mm"], None, "hematite")
    np.testing.assert_allclose(free.high, [3.0, 1000.0])
    assert free.sample(np.array([2.0, 250.0])).scattering_per_mm == 250.0
