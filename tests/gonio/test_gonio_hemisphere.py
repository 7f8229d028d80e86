import math

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.gonio import CollectorHemisphere


def uniform_hemisphere(n, seed):
    rng = np.random.default_rng(seed)
    z = rng.random(n)
    phi = 2 * math.pi * rng.random(n)
    s = np.sqrt(1 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)


def contains(bounds, dirs):
    """Closed-interval membership with a 1e-12 margin, periodic in azimuth."""
    phi = np.mod(np.arctan2(dirs[:, 1], dirs[:, 0]), 2 * math.pi)
    z0, z1, p0, p1 = bounds.T
    in_z = (dirs[:, 2] >= z0 - 1e-12) & (dirs[:, 2] <= z1 + 1e-12)
    in_phi = lambda p: (p >= p0 - 1e-12) & (p <= p1 + 1e-12)  # noqa: E731
    return in_z & (in_phi(phi) | in_phi(phi - 2 * math.pi) | in_phi(phi + 2 * math.pi))


class TestGeometry:
    def test_paper_hemisphere_has_901_patches(self, hemisphere):
        assert hemisphere.n_patches == 901
        assert hemisphere.n_bands == 30
        assert hemisphere.centroids.shape == (901, 3)
        assert hemisphere.bounds.shape == (901, 4)
        assert hemisphere.bounds[0, 0] == pytest.approx(1 - 1 / 901, abs=1e-15)

    @pytest.mark.parametrize("stacks, slices", [(31, 30), (2, 1), (5, 7), (12, 4)])
    def test_solid_angles_equal_and_sum_to_2pi(self, stacks, slices):
        h = CollectorHemisphere(stacks, slices)
        r = h.n_patches
        np.testing.assert_allclose(h.solid_angles, 2 * math.pi / r, rtol=1e-12)
        assert h.solid_angles.sum() == pytest.approx(2 * math.pi, rel=1e-13)

    @pytest.mark.parametrize("stacks, slices", [(31, 30), (2, 1), (5, 7)])
    def test_projected_solid_angles_sum_to_pi(self, stacks, slices):
        h = CollectorHemisphere(stacks, slices)
        z0, z1 = h.bounds[:, 0], h.bounds[:, 1]
        assert h.projected_solid_angles.sum() == pytest.approx(math.pi, rel=1e-13)
        # Band patches: π(z1² − z0²)/slices; cap: π t(2 − t), t = 1/r (docs/model.md §3).
        np.testing.assert_allclose(
            h.projected_solid_angles[1:], math.pi * (z1[1:] ** 2 - z0[1:] ** 2) / slices, rtol=1e-12
        )
        t = 1 / h.n_patches
        assert h.projected_solid_angles[0] == pytest.approx(math.pi * t * (2 - t), rel=1e-12)

    def test_layout_bands_top_down_slices_by_azimuth(self):
        h = CollectorHemisphere(4, 3)
        np.testing.assert_array_equal(h.band, [0, 1, 1, 1, 2, 2, 2, 3, 3, 3])
        np.testing.assert_array_equal(h.slice, [0, 0, 1, 2, 0, 1, 2, 0, 1, 2])
        np.testing.assert_allclose(h.bounds[1:4, 2], [0, 2 * math.pi / 3, 4 * math.pi / 3], atol=1e-15)
        # Band edges: z = j·slices/r counted from the horizon; r = 10.
        np.testing.assert_allclose(h.bounds[[1, 4, 7], 0], [0.6, 0.3, 0.0], atol=1e-15)
        np.testing.assert_allclose(h.band_cos_theta, [1.0, 0.75, 0.45, 0.15], atol=1e-15)


class TestPatchIndex:
    @pytest.mark.parametrize("stacks, slices", [(31, 30), (2, 1), (4, 3), (9, 16)])
    def test_random_directions_map_to_the_patch_whose_bounds_contain_them(self, stacks, slices):
        h = CollectorHemisphere(stacks, slices)
        dirs = uniform_hemisphere(100_000, seed=stacks)
        idx = h.patch_index(dirs)
        assert contains(h.bounds[idx], dirs).all()
        # Equal solid angles and uniform directions: every patch receives some.
        assert np.bincount(idx, minlength=h.n_patches).min() > 0

    @pytest.mark.parametrize("stacks, slices", [(31, 30), (2, 1), (3, 2), (6, 5)])
    def test_centroids_map_to_their_own_patch(self, stacks, slices):
        h = CollectorHemisphere(stacks, slices)
        np.testing.assert_allclose(np.linalg.norm(h.centroids, axis=1), 1.0, atol=1e-15)
        np.testing.assert_array_equal(h.patch_index(h.centroids), np.arange(h.n_patches))

    def test_centroid_is_the_solid_angle_centre_in_cos_theta_and_phi(self, hemisphere):
        z0, z1, p0, p1 = hemisphere.bounds[1:].T
        c = hemisphere.centroids[1:]
        np.testing.assert_allclose(c[:, 2], 0.5 * (z0 + z1), atol=1e-15)
        np.testing.assert_allclose(np.mod(np.arctan2(c[:, 1], c[:, 0]), 2 * math.pi), 0.5 * (p0 + p1), atol=1e-12)
        np.testing.assert_array_equal(hemisphere.centroids[0], [0, 0, 1])

    def test_centroid_is_close_to_the_normalised_mean_direction(self, hemisphere):
        # ∫ω dΩ over a band patch: x, y from ∫√(1−z²)dz × (sin, −cos) differences, z from ∫z dz Δφ.
        z0, z1, p0, p1 = hemisphere.bounds[1:].T
        g = lambda z: 0.5 * (z * np.sqrt(1 - z * z) + np.arcsin(z))  # noqa: E731 ∫√(1−z²)dz
        s = g(z1) - g(z0)
        mean = np.stack(
            [s * (np.sin(p1) - np.sin(p0)), s * (np.cos(p0) - np.cos(p1)), 0.5 * (z1**2 - z0**2) * (p1 - p0)], axis=-1
        )
        mean /= np.linalg.norm(mean, axis=1, keepdims=True)
        angle = np.degrees(np.arccos(np.clip((mean * hemisphere.centroids[1:]).sum(axis=1), -1, 1)))
        # The documented offsets: 0.52° in the top band (2.7°–15.1°), < 0.12° below it.
        assert angle[:30].max() < 0.53
        assert angle[30:].max() < 0.12

    def test_shape_broadcasting_and_scale(self, hemisphere):
        dirs = uniform_hemisphere(10, seed=3).reshape(2, 5, 3)
        idx = hemisphere.patch_index(dirs)
        assert idx.shape == (2, 5) and idx.dtype == np.int64
        np.testing.assert_array_equal(hemisphere.patch_index(dirs * 7.5), idx)
        assert hemisphere.patch_index([0.0, 0.0, 1.0]).shape == ()

    def test_horizon_and_rounding_below_it(self, hemisphere):
        idx = hemisphere.patch_index([[1.0, 0.0, 0.0], [1.0, 0.0, -1e-12], [0.0, -1.0, 0.0]])
        assert list(hemisphere.band[idx]) == [30, 30, 30]
        assert list(hemisphere.slice[idx]) == [0, 0, 22]  # φ = 3π/2 is in slice 22 of 30

    @pytest.mark.parametrize("bad", [[0.0, 0.0, 0.0], [np.nan, 0.0, 1.0], [np.inf, 0.0, 1.0], [0.0, 0.6, -0.8]])
    def test_invalid_directions_are_parameter_errors(self, hemisphere, bad):
        with pytest.raises(ParameterError, match="dirs"):
            hemisphere.patch_index([[0.0, 0.0, 1.0], bad])

    def test_wrong_shape_is_a_parameter_error(self, hemisphere):
        with pytest.raises(ParameterError, match=r"\(\.\.\., 3\)"):
            hemisphere.patch_index(np.zeros((4, 2)))


class TestValidation:
    @pytest.mark.parametrize(
        "stacks, slices, name",
        [
            (1, 30, "stacks"),
            (31, 0, "slices"),
            (2.5, 3, "stacks"),
            (True, 3, "stacks"),
            (31, 10_001, "slices"),
            ("31", 30, "stacks"),
        ],
    )
    def test_invalid_sizes(self, stacks, slices, name):
        with pytest.raises(ParameterError, match=name):
            CollectorHemisphere(stacks, slices)

    def test_equality_and_geometry_is_read_only(self):
        assert CollectorHemisphere() == CollectorHemisphere(31, 30) != CollectorHemisphere(31, 29)
        with pytest.raises(ValueError):
            CollectorHemisphere().centroids[0, 0] = 2.0
