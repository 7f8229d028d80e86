import math

import numpy as np
import pytest
from scipy import integrate

from sandlight.errors import ParameterError
from sandlight.testing.chandrasekhar import brdf, dhr, h_function

# Chandrasekhar (1950), table XI, conservative isotropic scattering (ω = 1).
TABLE_OMEGA_1 = [(0.0, 1.0), (0.05, 1.13657), (0.1, 1.24735), (0.5, 2.01278), (1.0, 2.90781)]


def quad(f, lo=0.0, hi=1.0):
    # Adaptive quadrature, independent of the solver's own Gauss–Legendre nodes.
    return integrate.quad(f, lo, hi, epsabs=1e-13, epsrel=1e-12, limit=200, points=[1e-6, 1e-3])[0]


class TestHFunction:
    @pytest.mark.parametrize("mu, expected", TABLE_OMEGA_1)
    def test_chandrasekhar_table_conservative(self, mu, expected):
        assert float(h_function(mu, 1.0)) == pytest.approx(expected, abs=1e-5)

    @pytest.mark.parametrize("omega", [0.1, 0.5, 0.9, 0.99, 1.0])
    def test_zeroth_moment_identity(self, omega):
        # α0 = ∫₀¹ H dμ = 2(1 − √(1 − ω))/ω (Chandrasekhar 1950, ch. V).
        alpha0 = quad(lambda m: float(h_function(m, omega)))
        assert alpha0 == pytest.approx(2 * (1 - math.sqrt(1 - omega)) / omega, rel=1e-9)

    def test_first_moment_conservative(self):
        # α1 = ∫₀¹ H μ dμ = 2/√3 for ω = 1.
        assert quad(lambda m: m * float(h_function(m, 1.0))) == pytest.approx(2 / math.sqrt(3), rel=1e-9)

    @pytest.mark.parametrize("omega", [0.3, 0.9, 1.0])
    @pytest.mark.parametrize("mu", [0.0, 0.02, 0.3, 0.77, 1.0])
    def test_satisfies_the_first_form_of_the_integral_equation(self, omega, mu):
        # H(μ) = 1 + (ω/2) μ H(μ) ∫₀¹ H(μ')/(μ + μ') dμ', evaluated with adaptive quadrature.
        if mu == 0.0:
            assert float(h_function(0.0, omega)) == pytest.approx(1.0, abs=1e-13)
            return
        integral = quad(lambda m: float(h_function(m, omega)) / (mu + m))
        h = float(h_function(mu, omega))
        assert h == pytest.approx(1 + 0.5 * omega * mu * h * integral, rel=1e-9)

    def test_shapes_monotonicity_and_nan(self):
        mu = np.linspace(0, 1, 12).reshape(3, 4)
        h = h_function(mu, 0.9)
        assert h.shape == (3, 4)
        assert np.all(np.diff(h.ravel()) > 0)
        np.testing.assert_array_equal(h_function(mu, 0.0), 1.0)
        assert np.isnan(h_function(np.nan, 0.9))

    @pytest.mark.parametrize(
        "mu, omega, name",
        [(1.2, 0.5, "mu"), (-0.1, 0.5, "mu"), (0.5, 1.01, "omega"), (0.5, -0.1, "omega"), (0.5, "x", "omega")],
    )
    def test_invalid_input(self, mu, omega, name):
        with pytest.raises(ParameterError, match=name):
            h_function(mu, omega)


class TestReflection:
    @pytest.mark.parametrize("omega", [0.5, 0.9, 1.0])
    @pytest.mark.parametrize("mu0", [0.05, 0.5, 1.0])
    def test_dhr_is_the_integral_of_the_brdf(self, omega, mu0):
        # ρ(μ0) = 2π ∫₀¹ f(μ, μ0) μ dμ = 1 − H(μ0)√(1 − ω) (docs/model.md §2.7).
        integral = 2 * math.pi * quad(lambda m: float(brdf(m, mu0, omega)) * m)
        assert integral == pytest.approx(float(dhr(mu0, omega)), rel=1e-9)

    def test_conservative_medium_reflects_everything(self):
        np.testing.assert_allclose(dhr(np.linspace(0, 1, 5), 1.0), 1.0, atol=1e-15)

    def test_brdf_is_reciprocal_and_broadcasts(self):
        mu = np.linspace(0.05, 1, 7)
        f = brdf(mu[:, None], mu[None, :], 0.8)
        assert f.shape == (7, 7)
        np.testing.assert_allclose(f, f.T, rtol=1e-15)
        # Single scattering dominates at small ω: f → ω/(4π(μ + μ0)).
        assert float(brdf(0.5, 0.5, 1e-6)) == pytest.approx(1e-6 / (4 * math.pi), rel=1e-6)

    def test_brdf_undefined_at_double_grazing(self):
        with pytest.raises(ParameterError, match="mu \\+ mu0"):
            brdf(0.0, 0.0, 0.5)
