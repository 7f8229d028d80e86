import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.predictor.monomials import monomial_plan, monomials


@pytest.mark.parametrize("degree, d", [(1, 3), (2, 5), (3, 13), (4, 4)])
def test_equals_polynomial_features(degree, d):
    from sklearn.preprocessing import PolynomialFeatures

    X = np.random.default_rng(degree).uniform(-1, 1, (37, d))
    poly = PolynomialFeatures(degree).fit(X)
    plan = monomial_plan(poly.powers_)
    F = monomials(np.ascontiguousarray(X.T), plan, poly.n_output_features_, np.empty((poly.n_output_features_, 64)))
    np.testing.assert_allclose(F.T, poly.transform(X), rtol=1e-14, atol=1e-15)
    if degree == 3 and d == 13:
        assert len(plan) <= 3 * d + 1  # a few numpy calls, not one per monomial


@pytest.mark.parametrize(
    "powers, message",
    [
        ([[1, 0], [0, 0]], "constant 1"),  # the constant is not first
        ([[0, 0], [0, 2], [0, 1]], "after its parent"),  # b² before b
        ([[0, 0], [1, 1]], "after its parent"),  # ab without a
    ],
)
def test_exponents_out_of_order_are_refused(powers, message):
    with pytest.raises(ParameterError, match=message):
        monomial_plan(powers)
