"""Free and fixed parameters of a fit: checks, bounds, the sample they make."""

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.retrieval.space import ParameterSpace
from sandlight.sample import SandSample


def test_bounds_come_from_the_sample_domain_and_narrow():
    space = ParameterSpace.build("iron_oxide,saturation")
    np.testing.assert_array_equal(space.low, [0.0, 0.0])
    np.testing.assert_array_equal(space.high, [0.10, 1.0])
    narrow = space.narrowed(np.array([0.001, 0.15]), np.array([0.05, 2.0]))
    np.testing.assert_array_equal(narrow.low, [0.001, 0.15])
    np.testing.assert_array_equal(narrow.high, [0.05, 1.0])
    assert narrow.sample(np.array([0.5, 0.5])).iron_oxide == 0.05  # clipped to the bounds


def test_fixed_values_and_derived_sand():
    space = ParameterSpace.build(["silt"], {"clay": 0.02, "grain_size": 0.5}, SandSample(porosity=0.3))
    s = space.sample(np.array([0.08]))
    assert (s.silt, s.clay, s.grain_size, s.porosity) == (0.08, 0.02, 0.5, 0.3)
    assert s.sand == pytest.approx(0.90)


@pytest.mark.parametrize(
    ("free", "fixed", "message"),
    [
        ([], None, "non-empty"),
        (["colour"], None, "not a sample parameter"),
        (["sand"], None, "cannot be fitted"),
        (["iron_oxide_form"], None, "cannot be fitted"),
        (["iron_oxide", "iron_oxide"], None, "each parameter once"),
        (["iron_oxide"], {"iron_oxide": 0.01}, "also free"),
        (["iron_oxide"], {"saturation": 2.0}, r"\[0, 1\]"),
        (["iron_oxide"], {"wetness": 0.5}, "not a sample parameter"),
    ],
)
def test_bad_free_or_fixed_is_named(free, fixed, message):
    with pytest.raises(ParameterError, match=message):
        ParameterSpace.build(free, fixed)
