"""sandlight.errors: messages name parameter, value and domain, and stay one readable line."""

import numpy as np
import pytest

from sandlight.errors import MAX_QUOTED, ParameterError
from sandlight.sample import SandSample


def test_a_huge_value_is_quoted_shortened_with_its_length():
    value = "x" * 5_000_000
    error = ParameterError("iron_oxide", value, "a real number in [0, 0.1]")
    message = str(error)
    assert len(message) < MAX_QUOTED + 200
    assert message.startswith("iron_oxide = 'xxx") and "…" in message
    assert "5,000,000 characters in all" in message and message.endswith("a real number in [0, 0.1]")
    assert error.value is value  # the attribute keeps the whole value


def test_a_long_repr_and_a_long_name_are_cut_too():
    message = str(ParameterError("k" * 1000, list(range(10_000)), "allowed"))
    assert len(message) < 2 * MAX_QUOTED + 200
    assert "1,000 characters in all" in message and "[0, 1, 2" in message


def test_short_values_are_quoted_whole():
    assert str(ParameterError("rays", 0, "an integer >= 1")) == "rays = 0 is not allowed: an integer >= 1"
    assert str(ParameterError("x", b"ab", "y")) == "x = b'ab' is not allowed: y"


def test_an_unknown_sample_key_of_a_megabyte_gives_a_short_message():
    with pytest.raises(ParameterError) as info:
        SandSample.from_dict({"q" * 1_000_000: np.float64(1.0)})
    assert len(str(info.value)) < 2 * MAX_QUOTED + 400
