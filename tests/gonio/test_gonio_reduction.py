import math

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.gonio import CollectorHemisphere, EquivalenceClasses, reduce_counts, reduce_fixed_incidence
from sandlight.testing import synthetic_brdf


def check_z_scores(z, *, mean_tol):
    """Honest standard errors: z-scores of a correct estimate are ~N(0, 1)."""
    assert np.all(np.isfinite(z))
    assert np.mean(np.abs(z) < 4) > 0.999
    assert np.abs(z).max() < 5.5
    assert 0.97 < z.std() < 1.03
    assert abs(z.mean()) < mean_tol


class TestLambertian:
    def test_absolute_values_are_a_over_pi_within_error(self, hemisphere, lambert_counts, lambert_albedo):
        red = reduce_counts(hemisphere, **lambert_counts)
        z = (red.unique_absolute - lambert_albedo / math.pi) / red.unique_absolute_stderr
        # 13 561 nearly independent classes: the mean of z is known to ±0.009.
        check_z_scores(z, mean_tol=0.05)
        rel = red.unique_absolute_stderr / red.unique_absolute
        assert np.median(rel) < 0.03  # ~1e8 trials give a few % per class

    def test_normalised_values_are_one_over_pi_within_error(self, hemisphere, lambert_counts, lambert_albedo):
        red = reduce_counts(hemisphere, **lambert_counts)
        assert abs(red.normal_reflectance - lambert_albedo) < 4 * red.normal_reflectance_stderr
        z = (red.unique_values - 1 / math.pi) / red.unique_stderr
        # All normalised values share the error of R, so their mean z moves with it (±0.1 or so).
        check_z_scores(z, mean_tol=0.35)

    def test_lost_trials_count_in_n_i(self, hemisphere, lambert_probabilities, lambert_albedo):
        counts = synthetic_brdf.sample_counts(hemisphere, lambert_probabilities, 10**8, seed=5, lost_probability=0.25)
        assert counts["lost"].sum() == pytest.approx(0.25e8, rel=1e-3)
        red = reduce_counts(hemisphere, **counts)
        z = (red.unique_absolute - 0.75 * lambert_albedo / math.pi) / red.unique_absolute_stderr
        check_z_scores(z, mean_tol=0.05)


class TestChandrasekhar:
    def test_matches_the_patch_averaged_analytic_brdf(
        self, hemisphere, chandrasekhar_counts, chandrasekhar_probabilities
    ):
        red = reduce_counts(hemisphere, **chandrasekhar_counts)
        classes = EquivalenceClasses(hemisphere)
        expected = classes.mean(synthetic_brdf.expected_brdf(hemisphere, chandrasekhar_probabilities))
        check_z_scores((red.unique_absolute - expected) / red.unique_absolute_stderr, mean_tol=0.05)
        # Normalised: E[f̂] = E[f̄] / R with R = Σ_k ω_p(k) E[f̄][c, k].
        r_true = float((classes.expand(expected)[0] * hemisphere.projected_solid_angles).sum())
        assert abs(red.normal_reflectance - r_true) < 4 * red.normal_reflectance_stderr
        check_z_scores((red.unique_values - expected / r_true) / red.unique_stderr, mean_tol=0.35)

    def test_normal_reflectance_is_the_analytic_dhr(self, hemisphere, chandrasekhar_counts, omega):
        from sandlight.testing.chandrasekhar import dhr

        red = reduce_counts(hemisphere, **chandrasekhar_counts)
        # The cap spans μ ∈ [1 − 1/901, 1]: its average DHR differs from ρ(1) by ~4e-5.
        assert red.normal_reflectance == pytest.approx(float(dhr(1.0, omega)), abs=4 * red.normal_reflectance_stderr)
        # Reciprocity adds the cap column to the cap row: better than the binomial error of the
        # cap row alone.
        n_cap = chandrasekhar_counts["launched"][0]
        r = red.normal_reflectance
        assert red.normal_reflectance_stderr < math.sqrt(r * (1 - r) / n_cap)

    def test_values_match_the_point_brdf_at_the_centroids(self, hemisphere, chandrasekhar_counts, omega):
        # Away from grazing the patch average is close to the BRDF at the centroids.
        from sandlight.testing.chandrasekhar import brdf

        red = reduce_counts(hemisphere, **chandrasekhar_counts)
        classes = EquivalenceClasses(hemisphere)
        mu = hemisphere.band_cos_theta
        point = brdf(mu[classes.band_in], mu[classes.band_out], omega)
        keep = (mu[classes.band_in] > 0.3) & (mu[classes.band_out] > 0.3)
        rel = np.abs(red.unique_absolute[keep] / point[keep] - 1)
        assert np.median(rel) < 0.03
        assert np.mean(rel < 4 * red.unique_absolute_stderr[keep] / point[keep] + 0.01) > 0.99


class TestPooled:
    def test_pooled_is_unbiased_and_tighter(self, hemisphere, chandrasekhar_counts, chandrasekhar_probabilities):
        classes = EquivalenceClasses(hemisphere)
        expected = classes.mean(synthetic_brdf.expected_brdf(hemisphere, chandrasekhar_probabilities))
        pooled = reduce_counts(hemisphere, **chandrasekhar_counts, method="pooled")
        average = reduce_counts(hemisphere, **chandrasekhar_counts)
        # The class expectation of both estimators is the same up to the spread of the N_i.
        check_z_scores((pooled.unique_absolute - expected) / pooled.unique_absolute_stderr, mean_tol=0.05)
        # Never worse (the 1 % allows for the two estimates entering their own error models).
        assert np.all(pooled.unique_absolute_stderr <= 1.01 * average.unique_absolute_stderr)
        grazing_cap = classes.cap_classes & (classes.band_out == 30)
        assert pooled.unique_absolute_stderr[grazing_cap][0] < 0.5 * average.unique_absolute_stderr[grazing_cap][0]

    def test_unknown_method(self, hemisphere, lambert_counts):
        with pytest.raises(ParameterError, match="method"):
            reduce_counts(hemisphere, **lambert_counts, method="median")


class TestStandardErrorsAcrossRuns:
    def test_scatter_over_seeds_matches_the_stated_errors(self):
        # Small hemisphere, many independent runs: the empirical scatter of R and of the values
        # equals the predicted standard errors (30 runs: ±13 % on a standard deviation).
        h = CollectorHemisphere(7, 6)
        p = synthetic_brdf.chandrasekhar_probabilities(h, 0.8)
        runs = [reduce_counts(h, **synthetic_brdf.sample_counts(h, p, 200_000, seed=s)) for s in range(30)]
        r = np.array([x.normal_reflectance for x in runs])
        r_se = np.mean([x.normal_reflectance_stderr for x in runs])
        assert 0.7 < r.std(ddof=1) / r_se < 1.3
        values = np.array([x.unique_values for x in runs])
        stderr = np.array([x.unique_stderr for x in runs]).mean(axis=0)
        ratio = values.std(axis=0, ddof=1) / stderr
        assert 0.9 < np.median(ratio) < 1.1
        cap = EquivalenceClasses(h).cap_classes  # strongly correlated with R
        assert 0.75 < np.median(ratio[cap]) < 1.25


class TestExactProperties:
    @pytest.fixture(scope="class")
    @classmethod
    def reduced(cls, hemisphere, chandrasekhar_counts):
        return reduce_counts(hemisphere, **chandrasekhar_counts)

    def test_reciprocity_and_isotropy_hold_exactly(self, hemisphere, reduced):
        full = EquivalenceClasses(hemisphere).expand(reduced.unique_values)
        np.testing.assert_array_equal(full, full.T)
        # Rotation by one slice about the normal.
        rot = np.where(hemisphere.band == 0, 0, 1 + (hemisphere.band - 1) * 30 + (hemisphere.slice + 1) % 30)
        np.testing.assert_array_equal(full[np.ix_(rot, rot)], full)

    def test_unit_reflectance_at_normal_incidence(self, hemisphere, reduced):
        full = EquivalenceClasses(hemisphere).expand(reduced.unique_values)
        assert float(full[hemisphere.cap] @ hemisphere.projected_solid_angles) == pytest.approx(1.0, abs=1e-13)

    def test_compress_expand_round_trip(self, hemisphere, reduced):
        c = EquivalenceClasses(hemisphere)
        np.testing.assert_array_equal(c.compress(c.expand(reduced.unique_values)), reduced.unique_values)

    def test_reflectance_varies_with_incidence(self, hemisphere, reduced):
        # The normalisation uses the cap row only: other rows keep their own reflectance.
        full = EquivalenceClasses(hemisphere).expand(reduced.unique_values)
        rho = full @ hemisphere.projected_solid_angles
        # ρ(μ0) = 1 − H(μ0)√(1 − ω) is largest at grazing incidence, where H → 1: 0.67 vs 0.415.
        assert rho[-1] > 1.4 * rho[0]


class TestInput:
    def test_rows_without_incidence(self):
        h = CollectorHemisphere(3, 2)
        counts = np.zeros((5, 5), dtype=np.int64)
        counts[1, 2] = 3
        launched = np.array([0, 4, 0, 0, 0])
        red = reduce_counts(h, counts, np.array([0, 1, 0, 0, 0]), launched, np.zeros(5, dtype=np.int64))
        c = EquivalenceClasses(h)
        full_members = c.expand(red.members)
        assert full_members[1, 2] == np.count_nonzero((c.class_of == c.class_of[1, 2]) & (launched[:, None] > 0))
        # Only row 1 has trials; classes without any entry in it are NaN, the others finite.
        seen = np.isin(np.arange(c.n_classes), c.class_of[1])
        assert np.all(np.isnan(red.unique_absolute[~seen])) and np.all(np.isfinite(red.unique_absolute[seen]))

    def test_launched_must_balance(self, hemisphere, lambert_counts):
        bad = dict(lambert_counts)
        bad["launched"] = bad["launched"] + np.eye(1, 901, 7, dtype=np.int64)[0]
        with pytest.raises(ParameterError, match="launched.*incoming patch 7"):
            reduce_counts(hemisphere, **bad)

    @pytest.mark.parametrize(
        "name, value", [("counts", np.zeros((900, 901))), ("absorbed", -np.ones(901)), ("lost", np.full(901, 0.5))]
    )
    def test_invalid_counters(self, hemisphere, lambert_counts, name, value):
        bad = dict(lambert_counts)
        bad[name] = value
        with pytest.raises(ParameterError, match=name):
            reduce_counts(hemisphere, **bad)


class TestWeightSums:
    """Sums of trial weights with Σ F² (shared paths): the error model with the second moment."""

    def test_indicator_weights_reduce_exactly_as_counts(self, hemisphere, lambert_counts):
        # F ∈ {0, 1}: Σ F² = Σ F, so the weighted reduction is the multinomial one.
        c = lambert_counts
        as_counts = reduce_counts(hemisphere, **c)
        as_weights = reduce_counts(
            hemisphere, **{k: np.asarray(v, dtype=float) for k, v in c.items()}, squares=np.asarray(c["counts"], float)
        )
        assert as_weights.equals(as_counts)

    def test_heavier_second_moments_widen_the_errors(self, hemisphere, lambert_counts):
        # Weights 2 on half the trials of every cell and 0 on the rest: the same Σ F, twice Σ F².
        c = {k: np.asarray(v, dtype=float) for k, v in lambert_counts.items()}
        base = reduce_counts(hemisphere, **c, squares=c["counts"])
        doubled = reduce_counts(hemisphere, **c, squares=2.0 * c["counts"])
        np.testing.assert_array_equal(doubled.unique_absolute, base.unique_absolute)
        assert np.all(doubled.unique_absolute_stderr > base.unique_absolute_stderr)
        assert doubled.normal_reflectance_stderr > base.normal_reflectance_stderr

    @pytest.mark.parametrize(
        "name, value, fault",
        [
            ("squares", np.zeros((900, 901)), "shape"),
            ("squares", np.full((901, 901), np.nan), "finite"),
            ("counts", -np.ones((901, 901)), "non-negative"),
        ],
    )
    def test_invalid_sums_name_the_array(self, hemisphere, lambert_counts, name, value, fault):
        c = {k: np.asarray(v, dtype=float) for k, v in lambert_counts.items()}
        sums = {**c, "squares": c["counts"], name: value}
        with pytest.raises(ParameterError, match=f"{name}.*{fault}"):
            reduce_counts(hemisphere, **sums)

    def test_launched_must_balance_the_weights(self, hemisphere, lambert_counts):
        c = {k: np.asarray(v, dtype=float) for k, v in lambert_counts.items()}
        c["absorbed"][3] += 0.5
        with pytest.raises(ParameterError, match="launched.*incoming patch 3"):
            reduce_counts(hemisphere, **c, squares=c["counts"])


class TestFixedIncidence:
    def test_lambertian_row(self, hemisphere, lambert_probabilities, lambert_albedo):
        rng = np.random.default_rng(2)
        p = lambert_probabilities[0]
        draw = rng.multinomial(10**7, np.append(p, 1 - p.sum()))
        f, se = reduce_fixed_incidence(hemisphere, draw[:-1], draw[-1], 10**7)
        z = (f - lambert_albedo / math.pi) / se
        assert np.mean(np.abs(z) < 4) > 0.995 and 0.9 < z.std() < 1.1

    def test_balance_is_checked(self, hemisphere):
        with pytest.raises(ParameterError, match="launched"):
            reduce_fixed_incidence(hemisphere, np.ones(901, dtype=int), 0, 900)

    def test_weight_sums_of_indicators_give_the_binomial_errors(self, hemisphere, lambert_probabilities):
        # Weights 0 or 1: Σ F² = Σ F, so the errors from the squares are the binomial ones.
        p = lambert_probabilities[0]
        draw = np.random.default_rng(3).multinomial(10**6, np.append(p, 1 - p.sum()))
        f, se = reduce_fixed_incidence(hemisphere, draw[:-1], draw[-1], 10**6)
        weights = draw[:-1].astype(float)
        fs, ses = reduce_fixed_incidence(hemisphere, weights, float(draw[-1]), 10**6, 0.0, squares=weights)
        np.testing.assert_allclose(fs, f, rtol=1e-15)
        np.testing.assert_allclose(ses, se, rtol=1e-12)
        # Weight sums balance to 10⁻⁹ of the trials; the squares are checked like the counts.
        with pytest.raises(ParameterError, match="launched"):
            reduce_fixed_incidence(hemisphere, weights, draw[-1] + 0.01, 10**6, squares=weights)
        with pytest.raises(ParameterError, match="squares"):
            reduce_fixed_incidence(hemisphere, weights, draw[-1], 10**6, squares=weights[:-1])
