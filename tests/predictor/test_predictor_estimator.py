"""The estimator base shared by SpectralModel and SpatialModel: parameters from the signature, one
constraints table, one message style, fitted state."""

import inspect
from numbers import Integral, Real

import numpy as np
import pytest
from sklearn.base import clone

from sandlight.checks import Interval, StrOptions
from sandlight.errors import ParameterError, SandlightError
from sandlight.predictor import SpectralModel
from sandlight.predictor.estimator import Estimator
from sandlight.spatial import SpatialModel

MODELS = [SpectralModel, SpatialModel]


@pytest.mark.parametrize("cls", MODELS)
class TestBothModels:
    def test_parameters_come_from_the_signature(self, cls):
        model = cls(n_components=2, variance_threshold=0.5)
        params = model.get_params()
        assert list(params) == list(inspect.signature(cls).parameters)
        assert (params["n_components"], params["variance_threshold"]) == (2, 0.5)
        assert clone(model).get_params() == params
        assert repr(model) == f"{cls.__name__}(n_components=2, variance_threshold=0.5)"
        assert repr(cls()) == f"{cls.__name__}()"
        assert model.set_params(n_components=3) is model and model.n_components == 3
        with pytest.raises(ParameterError, match="bogus"):
            model.set_params(bogus=1)

    @pytest.mark.parametrize(
        "name, value, allowed",
        [
            ("n_components", True, "None or an integer >= 1"),  # SpectralModel accepted this
            ("n_components", 0, "None or an integer >= 1"),
            ("n_components", 2.0, "None or an integer >= 1"),
            ("variance_threshold", True, "a number in (0, 1]"),
            ("variance_threshold", 0.0, "a number in (0, 1]"),
            ("variance_threshold", float("nan"), "a number in (0, 1]"),
            ("variance_threshold", "0.9", "a number in (0, 1]"),
        ],
    )
    def test_the_same_values_are_refused_with_the_same_message(self, cls, name, value, allowed):
        with pytest.raises(ParameterError) as info:
            cls(**{name: value}).validate_params()
        assert (info.value.name, info.value.allowed) == (name, allowed)
        assert info.value.value is value

    def test_numpy_scalars_are_numbers(self, cls):
        cls(n_components=np.int64(2), variance_threshold=np.float32(0.9)).validate_params()

    def test_not_fitted(self, cls):
        with pytest.raises(SandlightError, match=f"this {cls.__name__} is not fitted yet"):
            cls().check_is_fitted()


@pytest.mark.parametrize(
    "params, name, allowed",
    [
        ({"degree": True}, "degree", "an integer in 1..4"),
        ({"degree": 5}, "degree", "an integer in 1..4"),
        ({"ridge": True}, "ridge", "a finite number >= 0"),
        ({"ridge": float("inf")}, "ridge", "a finite number >= 0"),
        ({"ridge": -1e-9}, "ridge", "a finite number >= 0"),
        ({"forms": "both"}, "forms", "one of ('separate', 'onehot')"),
    ],
)
def test_spectral_parameters(params, name, allowed):
    with pytest.raises(ParameterError) as info:
        SpectralModel(**params).validate_params()
    assert (info.value.name, info.value.allowed) == (name, allowed)


def test_spatial_scaling():
    with pytest.raises(ParameterError) as info:
        SpatialModel(scaling="log").validate_params()
    assert info.value.allowed == "one of ('relative', 'none', 'noise')"


def test_interval_bounds_and_descriptions():
    open_right = Interval(Real, 0, 1, closed="left")
    assert [open_right.admits(v) for v in (0, 0.5, 1, -0.1, np.float64(0.2), True)] == [
        True,
        True,
        False,
        False,
        True,
        False,
    ]
    assert str(open_right) == "a number in [0, 1)"
    assert str(Interval(Integral, None, 3, closed="neither")) == "an integer < 3"
    assert Interval(Integral, 1, None).admits(10**400)  # no float conversion of large integers
    assert not Interval(Real, None, None).admits(float("-inf"))
    assert str(StrOptions(("a", "b"))) == "one of ('a', 'b')"
    assert not StrOptions(("a",)).admits(["a"])


def test_constraints_table_must_match_the_signature():
    with pytest.raises(TypeError, match="exactly the __init__ parameters"):

        class Drifted(Estimator):  # a parameter without a declared constraint
            _parameter_constraints = {"alpha": [Interval(Real, 0, None)]}

            def __init__(self, alpha: float = 1.0, beta: int = 2) -> None:
                self.alpha, self.beta = alpha, beta
