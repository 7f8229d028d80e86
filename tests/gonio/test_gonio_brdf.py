import math

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.gonio import CollectorHemisphere, MeasuredBRDF
from sandlight.testing import synthetic_brdf


def random_upper(n, seed):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2])
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def rotate_z(d, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * d[..., 0] - s * d[..., 1], s * d[..., 0] + c * d[..., 1], d[..., 2]], axis=-1)


class TestFromCounts:
    def test_metadata_and_arrays(self, chandrasekhar_brdf, omega):
        b = chandrasekhar_brdf
        assert (b.stacks, b.slices, b.rays, b.seed, b.wavelength_nm) == (31, 30, 10**8, 12, 550.0)
        assert b.sample == {"medium": "isotropic", "omega": omega}
        assert b.reduction_method == "average"
        assert b.values.shape == b.stderr.shape == b.values_absolute.shape == (901, 901)
        assert b.unique_values.shape == (13561,)
        np.testing.assert_allclose(b.values * b.normal_reflectance, b.values_absolute, rtol=1e-13)
        assert not b.counts.flags.writeable

    def test_reduction_is_reproducible(self, chandrasekhar_counts, chandrasekhar_brdf):
        again = MeasuredBRDF.from_counts(
            **chandrasekhar_counts, sample={"medium": "isotropic", "omega": 0.9}, wavelength_nm=550, seed=12
        )
        assert again == chandrasekhar_brdf
        assert MeasuredBRDF.from_counts(**chandrasekhar_counts, seed=13) != chandrasekhar_brdf

    @pytest.mark.parametrize(
        "kwargs, name",
        [
            ({"wavelength_nm": -5}, "wavelength_nm"),
            ({"wavelength_nm": "red"}, "wavelength_nm"),
            ({"sample": {"x": object()}}, "sample"),
            ({"rays": -1}, "rays"),
            ({"seed": 1.5}, "seed"),
            ({"stacks": 1}, "stacks"),
            ({"method": "best"}, "method"),
        ],
    )
    def test_invalid_metadata(self, lambert_counts, kwargs, name):
        with pytest.raises(ParameterError, match=name):
            MeasuredBRDF.from_counts(**lambert_counts, **kwargs)

    def test_lost_defaults_to_zero(self):
        h = CollectorHemisphere(3, 2)
        c = synthetic_brdf.sample_counts(h, synthetic_brdf.lambertian_probabilities(h, 0.5), 10_000, seed=0)
        b = MeasuredBRDF.from_counts(c["counts"], c["absorbed"], c["launched"], stacks=3, slices=2)
        np.testing.assert_array_equal(b.lost, 0)
        assert b.rays == 10_000


class TestContinuousBRDF:
    def test_equals_patch_values_at_centroids(self, chandrasekhar_brdf, hemisphere):
        c = hemisphere.centroids
        np.testing.assert_allclose(
            chandrasekhar_brdf.f(c[:, None], c[None, :]), chandrasekhar_brdf.values_absolute, rtol=1e-12
        )
        np.testing.assert_allclose(
            chandrasekhar_brdf.f(c[:, None], c[None, :], normalised=True), chandrasekhar_brdf.values, rtol=1e-12
        )

    def test_reciprocal_at_random_pairs(self, chandrasekhar_brdf):
        wi, wo = random_upper(20_000, 1), random_upper(20_000, 2)
        np.testing.assert_allclose(chandrasekhar_brdf.f(wi, wo), chandrasekhar_brdf.f(wo, wi), rtol=1e-12)

    def test_isotropic_at_random_pairs(self, chandrasekhar_brdf):
        wi, wo = random_upper(20_000, 3), random_upper(20_000, 4)
        angle = 2.0  # rad, not a multiple of the slice width
        np.testing.assert_allclose(
            chandrasekhar_brdf.f(rotate_z(wi, angle), rotate_z(wo, angle)), chandrasekhar_brdf.f(wi, wo), rtol=1e-10
        )

    def test_continuous_including_the_pole(self, chandrasekhar_brdf):
        wo = random_upper(2_000, 5)
        pole = np.array([0.0, 0.0, 1.0])
        at_pole = chandrasekhar_brdf.f(pole, wo)
        # Directions a hair from the pole, at any azimuth, give the pole's value.
        for phi in (0.0, 1.0, 4.0):
            near = np.array([1e-9 * math.cos(phi), 1e-9 * math.sin(phi), 1.0])
            np.testing.assert_allclose(chandrasekhar_brdf.f(near, wo), at_pole, rtol=1e-7)
        # A small step anywhere changes the value a little (trilinear: Lipschitz).
        wi = random_upper(2_000, 6)
        step = wi + 1e-7 * random_upper(2_000, 7)
        np.testing.assert_allclose(chandrasekhar_brdf.f(step, wo), chandrasekhar_brdf.f(wi, wo), rtol=1e-4)

    def test_constant_brdf_is_reproduced_everywhere(self):
        # Noise-free Lambertian counts: every reduced value is a/π, so is the interpolant.
        h = CollectorHemisphere(7, 6)
        p = synthetic_brdf.lambertian_probabilities(h, 0.5)
        launched = np.full(h.n_patches, 10**12)
        counts = np.round(p * 10**12).astype(np.int64)
        b = MeasuredBRDF.from_counts(counts, launched - counts.sum(axis=1), launched, stacks=7, slices=6)
        values = b.f(random_upper(1000, 8), random_upper(1000, 9))
        np.testing.assert_allclose(values, 0.5 / math.pi, rtol=1e-9)
        np.testing.assert_allclose(
            b.f(random_upper(1000, 8), random_upper(1000, 9), normalised=True), 1 / math.pi, rtol=1e-9
        )

    def test_below_horizon_is_zero_and_nan_propagates(self, chandrasekhar_brdf):
        up = np.array([0.3, 0.1, 0.9])
        assert chandrasekhar_brdf.f(up, [0.5, 0.0, -0.5]) == 0.0
        assert chandrasekhar_brdf.f([1.0, 0.0, 0.0], up) == 0.0
        assert np.isnan(chandrasekhar_brdf.f(up, [np.nan, 0.0, 1.0]))
        assert chandrasekhar_brdf.f(up, up) > 0

    def test_broadcasting_and_length_invariance(self, chandrasekhar_brdf):
        wi, wo = random_upper(5, 10), random_upper(4, 11)
        grid = chandrasekhar_brdf.f(wi[:, None, :], wo[None, :, :])
        assert grid.shape == (5, 4)
        np.testing.assert_allclose(chandrasekhar_brdf.f(3 * wi[:, None, :], 0.2 * wo[None, :, :]), grid, rtol=1e-13)
        assert chandrasekhar_brdf.f(wi[0], wo[0]).shape == ()

    @pytest.mark.parametrize("bad", [[0.0, 0.0, 0.0], [np.inf, 0.0, 1.0], [1.0, 1.0]])
    def test_invalid_directions(self, chandrasekhar_brdf, bad):
        with pytest.raises(ParameterError, match="wo"):
            chandrasekhar_brdf.f([0.0, 0.0, 1.0], bad)

    def test_follows_the_analytic_brdf_between_centroids(self, chandrasekhar_brdf, omega):
        # Interpolation error plus statistical noise stay small away from grazing angles.
        from sandlight.testing.chandrasekhar import brdf

        wi, wo = random_upper(5000, 12), random_upper(5000, 13)
        keep = (wi[:, 2] > 0.3) & (wo[:, 2] > 0.3)
        rel = chandrasekhar_brdf.f(wi[keep], wo[keep]) / brdf(wo[keep, 2], wi[keep, 2], omega) - 1
        assert np.median(np.abs(rel)) < 0.03
