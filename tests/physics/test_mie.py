"""sandlight.physics.mie against miepython (Prahl), an independent Lorenz–Mie code.

Conventions (miepython 3.3): miepython writes an absorbing index as m = n − ik and returns the
complex conjugates of Bohren & Huffman's amplitudes. So sandlight's (m, x) is miepython's
(m̄, x); sandlight's S1, S2 are the conjugates of ``S1_S2(m̄, x, mu, norm="wiscombe")``, the
unnormalised amplitudes (Re S(0) = x² Q_ext/4); sandlight's phase function is
``i_unpolarized(m̄, x, mu, norm="one")``, ∫ p dΩ = 1 (miepython's default ``norm="albedo"``
integrates to ω instead).

Tolerances:
- Q_ext, Q_sca, g: relative 1e-8 (measured: below 1e-9). Where |m|x < 0.1 miepython's
  ``efficiencies_mx`` switches to Wiscombe's small-particle expansion, which agrees only to
  ~1e-6, so the reference there is miepython's exact series summed multipole by multipole
  (``n_pole``), and g the mean cosine of its phase function by Gauss–Legendre quadrature.
- Amplitudes: 1e-8 of |S(0)|; phase function 1e-8 of p + √(p p_max). miepython sums Wiscombe's
  n_max = x + 4.05 x^(1/3) + 2 terms, sandlight 2x^(1/3) + 1 more; sandlight's own series cut
  at Wiscombe's count differs from its full one by the same amounts as miepython does (up to
  2e-9 of |S(0)| at x = 300, measured). An amplitude error δ|S(0)| changes p by about
  2δ√(p p_max), large relative to p only deep in its minima.
"""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.physics import mie

miepython = pytest.importorskip("miepython", minversion="3.3")

WATER = 1.333
# Quartz, kaolinite, hematite (Querry-like and weak), magnetite; the same in water; a bubble in
# water and corners of the domain.
INDICES = [
    1.54 + 1e-8j,
    1.56 + 1e-4j,
    3.0 + 0.5j,
    2.6 + 0.05j,
    2.4 + 0.6j,
    (1.54 + 1e-8j) / WATER,
    (1.56 + 1e-4j) / WATER,
    (3.0 + 0.5j) / WATER,
    (2.4 + 0.6j) / WATER,
    1.0 / WATER,
    0.5 + 0j,
    0.5 + 5j,
    10 + 10j,
]
SIZES = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0]


def wiscombe_terms(x: float) -> int:
    return int(x + 4.05 * x ** (1 / 3) + 2)


def reference(m: complex, x: float) -> tuple[float, float, float]:
    """(Q_ext, Q_sca, g) from miepython for sandlight's index m."""
    mc = np.conj(m)
    if abs(m) * x >= 0.1:
        q_ext, q_sca, _, g = miepython.efficiencies_mx(mc, x)
        return float(q_ext), float(q_sca), float(g)
    q_ext = q_sca = 0.0
    for n in range(1, wiscombe_terms(x) + 1):
        for electric in (True, False):
            e, s, _, _ = miepython.efficiencies_mx(mc, x, n_pole=n, e_field=electric)
            q_ext, q_sca = q_ext + e, q_sca + s
    mu, w = np.polynomial.legendre.leggauss(wiscombe_terms(x) + 2)
    p = miepython.i_unpolarized(mc, x, mu, norm="one")
    return q_ext, q_sca, float(np.sum(w * mu * p) / np.sum(w * p))


class TestMieEfficiencies:
    @pytest.mark.parametrize("m", INDICES, ids=str)
    def test_against_miepython(self, m):
        e = mie.mie_efficiencies(m, SIZES)
        for i, x in enumerate(SIZES):
            q_ext, q_sca, g = reference(m, x)
            assert e.q_ext[i] == pytest.approx(q_ext, rel=1e-8), f"x = {x}"
            assert e.q_sca[i] == pytest.approx(q_sca, rel=1e-8), f"x = {x}"
            assert e.g[i] == pytest.approx(g, rel=1e-8, abs=1e-12), f"x = {x}"
            assert e.q_abs[i] == pytest.approx(e.q_ext[i] - e.q_sca[i], rel=1e-12, abs=1e-13 * e.q_ext[i])
            assert e.albedo[i] == pytest.approx(e.q_sca[i] / e.q_ext[i], rel=1e-14)

    def test_small_particle_expansion_of_miepython(self):
        # Where |m|x < 0.1 miepython's efficiencies_mx is Wiscombe's expansion: close, not exact.
        for m in (1.54 + 1e-8j, 3.0 + 0.5j, 0.5 + 0j):
            e = mie.mie_efficiencies(m, 0.03)
            q_ext, q_sca, _, g = miepython.efficiencies_mx(np.conj(m), 0.03)
            assert e.q_ext == pytest.approx(q_ext, rel=1e-5) and e.q_sca == pytest.approx(q_sca, rel=1e-5)
            assert e.g == pytest.approx(g, rel=1e-5)

    def test_non_absorbing_sphere_absorbs_nothing(self):
        e = mie.mie_efficiencies([1.5, 0.75, 1.54 / WATER], 50.0)
        np.testing.assert_array_equal(e.q_abs, 0.0)
        np.testing.assert_array_equal(e.albedo, 1.0)

    def test_broadcasting_and_scalars(self):
        m = np.array([[1.54 + 1e-8j], [3.0 + 0.5j]])
        x = np.array([0.5, 5.0, 50.0])
        e = mie.mie_efficiencies(m, x)
        for field in e:
            assert field.shape == (2, 3)
        assert e.q_sca[1, 2] == mie.mie_efficiencies(3.0 + 0.5j, 50.0).q_sca
        scalar = mie.mie_efficiencies(1.54, 2.0)
        assert np.ndim(scalar.q_ext) == 0 and isinstance(float(scalar.q_ext), float)
        assert mie.mie_efficiencies(np.empty(0), np.empty(0)).q_ext.shape == (0,)

    @pytest.mark.parametrize(
        ("m", "x", "name"),
        [
            (1.5, 0.0, "x"),
            (1.5, 3e4, "x"),
            (1.5, np.nan, "x"),
            (1.5, "big", "x"),
            (1.5 - 0.1j, 1.0, "m.imag"),
            (0.3, 1.0, "m.real"),
            (complex(np.nan, 0.0), 1.0, "m.real"),
            (1.0, 1.0, "m"),
            ("quartz", 1.0, "m"),
        ],
    )
    def test_bad_input_names_the_parameter(self, m, x, name):
        with pytest.raises(ParameterError) as err:
            mie.mie_efficiencies(m, x)
        assert err.value.name == name

    def test_nan_anywhere_in_an_array(self):
        with pytest.raises(ParameterError, match="NaN") as err:
            mie.mie_efficiencies(1.5, [1.0, np.nan, 2.0])
        assert err.value.name == "x"

    def test_shapes_that_do_not_broadcast(self):
        with pytest.raises(ParameterError) as err:
            mie.mie_efficiencies([1.5, 1.6], [1.0, 2.0, 3.0])
        assert err.value.name == "x"


class TestScatteringAmplitudes:
    @pytest.mark.parametrize("m", INDICES, ids=str)
    def test_against_miepython(self, m):
        mu = np.cos(np.linspace(0.0, np.pi, 181))
        for x in SIZES:
            s1, s2 = mie.scattering_amplitudes(m, x, mu)
            t1, t2 = miepython.S1_S2(np.conj(m), x, mu, norm="wiscombe")
            scale = abs(t1[0])
            assert np.max(np.abs(s1 - np.conj(t1))) < 1e-8 * scale, f"x = {x}"
            assert np.max(np.abs(s2 - np.conj(t2))) < 1e-8 * scale, f"x = {x}"

    def test_forward_amplitude_is_the_optical_theorem(self):
        # S1(0) = S2(0) and Q_ext = (4/x²) Re S(0) (Bohren & Huffman eq. 4.76).
        for m, x in ((3.0 + 0.5j, 7.0), (1.54 + 1e-8j, 120.0)):
            s1, s2 = mie.scattering_amplitudes(m, x, 1.0)
            assert s1 == pytest.approx(s2, rel=1e-13)
            assert 4.0 * s1.real / x**2 == pytest.approx(mie.mie_efficiencies(m, x).q_ext, rel=1e-10)

    def test_shape(self):
        s1, s2 = mie.scattering_amplitudes(2.4 + 0.6j, 3.0, np.zeros((2, 5)))
        assert s1.shape == s2.shape == (2, 5) and s1.dtype == complex

    def test_one_sphere_only(self):
        with pytest.raises(ParameterError) as err:
            mie.scattering_amplitudes([1.5, 1.6], 1.0, 0.0)
        assert err.value.name == "m"


class TestPhaseFunction:
    @pytest.mark.parametrize("m", INDICES, ids=str)
    def test_against_miepython(self, m):
        mu = np.cos(np.linspace(0.0, np.pi, 181))
        for x in SIZES:
            p = mie.phase_function(m, x, mu)
            ref = miepython.i_unpolarized(np.conj(m), x, mu, norm="one")
            tol = 1e-8 * (ref + np.sqrt(ref * ref.max()))
            assert np.all(np.abs(p - ref) <= tol), f"x = {x}: worst {np.max(np.abs(p - ref) / tol):.2f} of tolerance"

    @pytest.mark.parametrize(("m", "x"), [(1.56 + 1e-4j, 0.2), (3.0 + 0.5j, 15.0), (1.54 / WATER, 80.0)])
    def test_normalised_with_mean_cosine_g(self, m, x):
        # p is a polynomial of degree 2 n_max in μ: Gauss–Legendre with n_max + 1 nodes is exact
        # up to round-off, which reaches 1e-11 at x = 80 (the sum varies by that much with the
        # node count: node errors of 1e-16 against the slope of the forward peak).
        mu, w = np.polynomial.legendre.leggauss(wiscombe_terms(x) + 60)
        p = mie.phase_function(m, x, mu)
        assert 2 * np.pi * np.sum(w * p) == pytest.approx(1.0, abs=1e-10)
        assert 2 * np.pi * np.sum(w * mu * p) == pytest.approx(float(mie.mie_efficiencies(m, x).g), abs=1e-10)

    def test_shape_and_scalar(self):
        assert mie.phase_function(1.5, 2.0, np.zeros((3, 4))).shape == (3, 4)
        assert np.ndim(mie.phase_function(1.5, 2.0, 0.5)) == 0

    @pytest.mark.parametrize("mu", [1.5, -1.0000001, np.nan, [0.0, np.inf], "forward"])
    def test_bad_cosines(self, mu):
        with pytest.raises(ParameterError) as err:
            mie.phase_function(1.5, 2.0, mu)
        assert err.value.name == "mu"


class TestPhaseTable:
    def test_table_is_a_normalised_interpolant_of_the_phase_function(self):
        m, x = 2.6 + 0.05j, 40.0
        t = mie.phase_table(m, x)
        assert t.mu[0] == -1.0 and t.mu[-1] == 1.0 and np.all(np.diff(t.mu) > 0)
        assert t.cdf[0] == 0.0 and t.cdf[-1] == 1.0 and np.all(np.diff(t.cdf) >= 0)
        # Trapezoid integral of the table over the sphere is 1; node values are the exact phase
        # function up to that normalisation, within the documented interpolation accuracy.
        assert 2 * np.pi * np.trapezoid(t.pdf, t.mu) == pytest.approx(1.0, rel=1e-13)
        np.testing.assert_allclose(t.pdf, mie.phase_function(m, x, t.mu), rtol=2e-4)
        # Mean cosine of the interpolant: ∫ μ f dμ = h (a(2f_a + f_b) + b(f_a + 2f_b))/6 per interval.
        a, b, fa, fb = t.mu[:-1], t.mu[1:], t.pdf[:-1], t.pdf[1:]
        mean = 2 * np.pi * np.sum((b - a) * (a * (2 * fa + fb) + b * (fa + 2 * fb)) / 6)
        assert mean == pytest.approx(float(mie.mie_efficiencies(m, x).g), abs=1e-5)

    @pytest.mark.parametrize("x", [30.0, 100.0, 1000.0])
    def test_node_count(self, x):
        # 32 θ intervals per term, the 16/x forward peak four times finer; at least 512 intervals.
        assert mie.phase_table(1.5, 0.01).mu.size == 4 * 512 + 1
        n = 32 * int(x + 6 * x ** (1 / 3) + 3)
        refined = math.ceil(16 / x / (math.pi / n))
        assert mie.phase_table(1.5, x).mu.size == n + 1 + 3 * refined

    def test_bad_input(self):
        with pytest.raises(ParameterError):
            mie.phase_table(1.5, -1.0)


class TestSizeParameter:
    def test_values(self):
        assert mie.size_parameter(1.0, 1000.0 * np.pi) == pytest.approx(1.0, rel=1e-15)
        # Water shortens the wavelength in the host by 1.333.
        np.testing.assert_allclose(
            mie.size_parameter([0.2, 2.0], 550.0, WATER), np.pi * np.array([200.0, 2000.0]) * WATER / 550.0, rtol=1e-15
        )

    def test_broadcasting(self):
        assert mie.size_parameter(np.ones((2, 1)), np.array([400.0, 500.0, 600.0])).shape == (2, 3)
        with pytest.raises(ParameterError):
            mie.size_parameter([1.0, 2.0], [400.0, 500.0, 600.0])

    @pytest.mark.parametrize(
        ("args", "name"),
        [((0.0, 500.0), "diameter_um"), ((1.0, np.nan), "wavelength_nm"), ((1.0, 500.0, 0.9), "host_index")],
    )
    def test_bad_input(self, args, name):
        with pytest.raises(ParameterError) as err:
            mie.size_parameter(*args)
        assert err.value.name == name


def test_docstring_examples():
    result = doctest.testmod(mie, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
