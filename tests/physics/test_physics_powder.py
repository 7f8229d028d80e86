"""Tests of sandlight.physics.powder: a powder of one pure material as a traceable medium."""

import math

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.physics.medium import Traceable
from sandlight.physics.powder import Powder


def test_powder_composition_is_one_population_with_the_pore_space_mean_free_path():
    powder = Powder("hematite", 2.5, porosity=0.45)
    comp = powder.composition
    (pop,) = comp.populations
    assert pop.core == {"hematite": 1.0} and pop.coating == {} and pop.volume_fraction == 1.0
    # Equal spheres of diameter D: ⟨S⟩/⟨V⟩ = 6/D, and ℓ = 4φ / [(1 − φ) ⟨S⟩/⟨V⟩].
    assert pop.surface_per_volume_per_mm == pytest.approx(6.0 / 2.5e-3)
    assert comp.mean_free_path_mm == pytest.approx(4 * 0.45 / (0.55 * 6.0 / 2.5e-3))
    assert comp.film_thickness_mm == 0.0 and comp.water_filled_probability == 0.0 and math.isinf(comp.depth_mm)
    # A sieve fraction: equal mass per log size, so E_m[1/D] = (1/d_min − 1/d_max)/ln(d_max/d_min).
    sieve = Powder("quartz", (10.0, 100.0)).composition.populations[0]
    expected = 6.0 * (1 / 0.01 - 1 / 0.1) / math.log(10.0)
    assert sieve.surface_per_volume_per_mm == pytest.approx(expected, rel=1e-4)


def test_powder_is_traceable_and_describes_itself():
    powder = Powder("quartz", (10.0, 100.0), porosity=0.4, aspect_ratio=1.5)
    assert isinstance(powder, Traceable)
    assert powder.describe() == {
        "material": "quartz",
        "diameter_um": [10.0, 100.0],
        "porosity": 0.4,
        "aspect_ratio": 1.5,
    }


def test_opaque_powder_is_dark_and_transparent_powder_bright():
    quartz = sandlight.reflectance(Powder("quartz", (10.0, 100.0)), [500.0], rays=400, seed=3, progress=False)
    hematite = sandlight.reflectance(Powder("hematite", 2.5), [500.0], rays=400, seed=3, progress=False)
    # Hematite absorbs strongly at 500 nm (k ≈ 0.65); quartz is nearly transparent.
    assert hematite.values[0] < 0.2 < 0.7 < quartz.values[0]
    assert quartz.sample["diameter_um"] == [10.0, 100.0]
    assert (quartz.geometry, quartz.memory) == ("on-the-fly", "none")


def test_a_powder_takes_a_path_memory_as_a_sand_does():
    powder = Powder("hematite", (150.0, 250.0), memory="packed")
    assert powder.describe()["memory"] == "packed"
    r = sandlight.reflectance(powder, [500.0, 2000.0], rays=400, seed=3, progress=False)
    assert (r.memory, r.sample) == ("packed", Powder("hematite", (150.0, 250.0)).describe())
    with pytest.raises(ParameterError, match="memory"):
        Powder("quartz", 10.0, memory="full")


def test_powder_reflectance_of_validation_is_the_engine_on_the_powder():
    from sandlight.validation import powder_reflectance

    a = powder_reflectance("goethite", 2.5, [450.0, 650.0], rays=500, porosity=0.4, seed=7)
    b = sandlight.reflectance(Powder("goethite", 2.5, porosity=0.4), [450.0, 650.0], rays=500, seed=7, progress=False)
    for k in b.counts:
        np.testing.assert_array_equal(a.counts[k], b.counts[k])
    assert a.sample == b.sample


@pytest.mark.parametrize(
    "kwargs,name",
    [
        (dict(material="cheese", diameter_um=10.0), "material"),
        (dict(material="quartz", diameter_um=(100.0, 10.0)), "diameter_um"),
        (dict(material="quartz", diameter_um=-1.0), "diameter_um"),
        (dict(material="quartz", diameter_um="fine"), "diameter_um"),
        (dict(material="quartz", diameter_um=(1.0, 2.0, 3.0)), "diameter_um"),
        (dict(material="quartz", diameter_um=10.0, porosity=1.0), "porosity"),
        (dict(material="quartz", diameter_um=10.0, aspect_ratio=0.5), "aspect_ratio"),
    ],
)
def test_bad_powders_name_the_parameter(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        Powder(**kwargs)
