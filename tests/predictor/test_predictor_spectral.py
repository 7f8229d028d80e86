"""SpectralModel: PCA + cubic regression on problems with a known answer, inputs, domain."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from sandlight.errors import ParameterError, SandlightError
from sandlight.predictor import Domain, SpectralModel
from sandlight.predictor.monomials import BLOCK_SAMPLES

WL = np.arange(400.0, 701.0, 20.0)  # the paper's 16 wavelengths
#: A 5-parameter domain (56 cubic monomials) so that small training sets determine the fit.
SMALL = Domain.default().restrict(
    forms=["coating", "particles"],
    hematite_ratio=0.5,
    magnetite=0.0,
    coating_iron_share=0.5,
    iron_oxide_particle_size_um=1.0,
    film_saturation=0.0,
    porosity=0.4,
    grain_size_spread=1.5,
    aspect_ratio=1.5,
)


def as_array(domain, samples):
    return np.array([[s[n] for n in domain.names] for s in samples])


def exact_cubic_problem(domain, n, seed, rank=3):
    """Spectra that are exactly mean + (cubic polynomial of the scaled parameters) @ basis,
    with a different polynomial per form: the model must reproduce them to round-off."""
    from sklearn.preprocessing import PolynomialFeatures

    rng = np.random.default_rng(1234)
    d = len(domain.names)
    m = PolynomialFeatures(3).fit(np.zeros((1, d))).n_output_features_
    A = rng.standard_normal((len(domain.forms), m, rank)) * 0.02
    basis = np.linalg.qr(rng.standard_normal((len(WL), rank)))[0].T  # orthonormal rows
    mean = np.linspace(0.3, 0.6, len(WL))

    def spectra(samples):
        X = as_array(domain, samples)
        Phi = PolynomialFeatures(3).fit_transform(domain.scaled(X))
        codes = np.array([domain.forms.index(s["iron_oxide_form"]) for s in samples])
        return mean + np.einsum("nm,nmk->nk", Phi, A[codes]) @ basis

    train = domain.draw(n, seed)
    return train, spectra(train), spectra, basis


@pytest.fixture(scope="module")
def fitted():
    """Model fitted on the exact cubic problem, the problem's spectra function and basis."""
    train, R, spectra, basis = exact_cubic_problem(SMALL, 400, seed=3)
    return SpectralModel().fit(train, R, wavelengths_nm=WL, domain=SMALL), spectra, basis


class TestExactCubic:
    def test_pca_finds_the_rank_and_the_basis(self, fitted):
        model, _, basis = fitted
        assert model.n_components_ == 3
        assert model.explained_variance_ratio_[:3].sum() == pytest.approx(1.0, abs=1e-12)
        assert model.reconstruction_rms_ < 1e-12
        # the principal directions span the basis the data were built from
        projected = basis @ model.components_.T @ model.components_
        np.testing.assert_allclose(projected, basis, atol=1e-10)
        np.testing.assert_allclose(model.components_ @ model.components_.T, np.eye(3), atol=1e-12)

    def test_regression_is_exact_on_new_samples(self, fitted):
        model, spectra, _ = fitted
        fresh = SMALL.draw(200, seed=99, design="random")
        np.testing.assert_allclose(model.predict(fresh), spectra(fresh), atol=1e-10)
        assert model.training_rms_ < 1e-12

    def test_too_few_components_leave_the_expected_error(self):
        train, R, spectra, _ = exact_cubic_problem(SMALL, 400, seed=3)
        model = SpectralModel(n_components=2).fit(train, R, wavelengths_nm=WL, domain=SMALL)
        # Dropping the third direction leaves exactly the variance along it.
        ratio = model.explained_variance_ratio_
        total = ((R - R.mean(0)) ** 2).sum() / R.size
        assert model.reconstruction_rms_ == pytest.approx(np.sqrt(ratio[2] * total), rel=1e-9)

    def test_onehot_forms_also_reproduce_a_single_polynomial(self):
        # With one-hot inputs the form enters the monomials; data whose polynomial does not
        # depend on the form are fitted exactly as well.
        domain = SMALL.restrict(forms=["coating"])
        train, R, spectra, _ = exact_cubic_problem(domain, 300, seed=5)
        for s in train[::2]:
            s["iron_oxide_form"] = "particles"
        model = SpectralModel(forms="onehot").fit(train, R, wavelengths_nm=WL, domain=SMALL)
        fresh = domain.draw(50, seed=7, design="random")
        np.testing.assert_allclose(model.predict(fresh), spectra(fresh), atol=1e-9)
        assert model.W_.shape[0] == 1 and model.powers_.shape[1] == len(SMALL.names) + 1


class TestFastEvaluator:
    def test_blocks_and_mixed_forms(self):
        # More samples than one block, forms interleaved: the result must not depend on either.
        train, R, spectra, _ = exact_cubic_problem(SMALL, 400, seed=3)
        model = SpectralModel().fit(train, R, wavelengths_nm=WL, domain=SMALL)
        fresh = SMALL.draw(2 * BLOCK_SAMPLES + 17, seed=11, design="random")
        X = as_array(SMALL, fresh)
        codes = np.array([SMALL.forms.index(s["iron_oxide_form"]) for s in fresh])
        together = model.predict(X, codes)
        one_by_one = np.vstack([model.predict(X[i], codes[i : i + 1]) for i in range(0, len(X), 97)])
        np.testing.assert_allclose(together[::97], one_by_one, rtol=0, atol=1e-14)
        np.testing.assert_allclose(together, spectra(fresh), atol=1e-10)


@pytest.fixture
def model_and_samples(fitted):
    return fitted[0], SMALL.draw(10, seed=8)


class TestInputs:
    def test_every_container_gives_the_same_answer(self, model_and_samples):
        model, samples = model_and_samples
        expected = model.predict(samples)
        assert expected.shape == (10, len(WL))
        df = pd.DataFrame(samples)
        X = as_array(SMALL, samples)
        names = df["iron_oxide_form"].to_numpy()
        codes = np.array([model.forms_.index(f) for f in names])
        variants = [
            model.predict(df),
            model.predict(df.to_records(index=False)),
            model.predict(xr.Dataset.from_dataframe(df)),
            model.predict({k: df[k].to_numpy() for k in df.columns}),
            model.predict(X, codes),
            model.predict(X, names),
            model.predict(X, list(names)),
        ]
        for v in variants:
            np.testing.assert_array_equal(v, expected)

    def test_single_sample_gives_one_row(self, model_and_samples):
        model, samples = model_and_samples
        one = model.predict(samples[4])
        assert one.shape == (1, len(WL))
        # equal up to BLAS round-off, which may differ between batch sizes
        np.testing.assert_allclose(one[0], model.predict(samples)[4], rtol=0, atol=1e-14)

    def test_objects_with_to_dict(self, model_and_samples):
        model, samples = model_and_samples

        class Sample:  # duck-typed like SandSample
            def __init__(self, d):
                self.d = d

            def to_dict(self):
                return dict(self.d)

        np.testing.assert_array_equal(model.predict([Sample(s) for s in samples]), model.predict(samples))
        np.testing.assert_array_equal(model.predict(Sample(samples[0])), model.predict(samples[:1]))

    def test_bad_inputs(self, model_and_samples):
        model, samples = model_and_samples
        X = as_array(SMALL, samples)
        with pytest.raises(ParameterError, match="forms"):
            model.predict(X)  # two forms: form of each row needed
        with pytest.raises(ParameterError, match=r"\(n, 5\)"):
            model.predict(X[:, :4], "coating")
        with pytest.raises(ParameterError, match="iron_oxide_form = 'mixed'.*coating"):
            model.predict(X, "mixed")
        with pytest.raises(ParameterError, match="iron_oxide_form = 7"):
            model.predict(X, 7)
        missing = {k: v for k, v in samples[0].items() if k != "saturation"}  # takes the default, 0
        np.testing.assert_array_equal(model.predict(missing), model.predict({**missing, "saturation": 0.0}))
        with pytest.raises(ParameterError, match="forms = 'coating'.*named samples"):
            model.predict(samples, "coating")
        with pytest.raises(ParameterError, match="samples"):
            model.predict("red-dune")
        with pytest.raises(SandlightError, match="not fitted"):
            SpectralModel().predict(samples)


@pytest.fixture
def model(fitted):
    return fitted[0]


class TestDomainOfValidity:
    @pytest.mark.parametrize(
        "change, name",
        [
            ({"iron_oxide": 0.2}, "iron_oxide"),
            ({"grain_size": 0.01}, "grain_size"),
            ({"silt": 0.12, "clay": 0.05}, "silt + 1.5·clay"),
            ({"depth_mm": 5.0}, "depth_mm"),
        ],
    )
    def test_outside_raises_naming_the_parameter_unless_extrapolate(self, model, change, name):
        sample = {**SMALL.draw(1, seed=4)[0], **change}
        with pytest.raises(ParameterError, match="extrapolate=True") as info:
            model.predict(sample)
        assert info.value.name == name
        out = model.predict(sample, extrapolate=True)
        assert out.shape == (1, len(WL)) and np.isfinite(out).all()

    def test_extrapolation_continues_the_polynomial(self, model):
        # Just outside the domain the prediction moves continuously from the edge value.
        base = SMALL.draw(1, seed=4)[0]
        edge = model.predict({**base, "saturation": 1.0})
        beyond = model.predict({**base, "saturation": 1.0 + 1e-6}, extrapolate=True)
        np.testing.assert_allclose(beyond, edge, atol=1e-4)

    def test_fixed_parameter_values_are_checked(self, model):
        sample = {**SMALL.draw(1, seed=4)[0], "porosity": 0.3}
        with pytest.raises(ParameterError, match="porosity"):
            model.predict(sample)

    @pytest.mark.parametrize("extrapolate", [False, True])
    def test_impossible_values_always_raise(self, model, extrapolate):
        sample = SMALL.draw(1, seed=4)[0]
        with pytest.raises(ParameterError, match="grain_size.*> 0"):
            model.predict({**sample, "grain_size": -1.0}, extrapolate=True)
        with pytest.raises(ParameterError, match="iron_oxide = nan"):
            model.predict({**sample, "iron_oxide": float("nan")}, extrapolate=extrapolate)


class TestEstimatorConventions:
    def test_init_only_stores_and_fit_validates(self):
        model = SpectralModel(degree=9, ridge=-1)  # no error before fit
        assert model.get_params() == {
            "n_components": None,
            "variance_threshold": 0.999,
            "degree": 9,
            "ridge": -1,
            "forms": "separate",
            "regressor": "monomials",
            "hidden_units": 128,
            "hidden_layers": 2,
            "network_alpha": 1e-6,
            "ensemble": 1,
            "learning_rates": (1e-3,),
            "network_validation": "r2",
            "physical_inputs": (),
            "random_state": 0,
        }
        train, R, _, _ = exact_cubic_problem(SMALL, 100, seed=3)
        for bad in [
            {"degree": 9},
            {"ridge": -1.0},
            {"forms": "both"},
            {"n_components": 0},
            {"variance_threshold": 1.5},
            {"n_components": 17},
        ]:
            with pytest.raises(ParameterError, match=next(iter(bad))):
                SpectralModel(**bad).fit(train, R, wavelengths_nm=WL, domain=SMALL)

    def test_clone_and_set_params(self):
        from sklearn.base import clone

        model = SpectralModel(ridge=0.5, forms="onehot")
        assert clone(model).get_params() == model.get_params()
        assert model.set_params(degree=2).degree == 2
        assert repr(model) == "SpectralModel(degree=2, ridge=0.5, forms='onehot')"
        with pytest.raises(ParameterError):
            model.set_params(bogus=1)

    def test_ridge_shrinks_towards_the_mean_spectrum(self):
        train, R, _, _ = exact_cubic_problem(SMALL, 300, seed=3)
        norms = []
        for ridge in (0.0, 1.0, 1e12):
            m = SpectralModel(n_components=3, ridge=ridge).fit(train, R, wavelengths_nm=WL, domain=SMALL)
            norms.append(np.abs(m.W_[:, 1:]).sum())
        assert norms[0] > norms[1] > norms[2]
        # An overwhelming penalty leaves only the (unpenalised) constant: the mean spectrum of
        # the form's training samples.
        fresh = SMALL.draw(20, seed=9)
        preds = m.predict(fresh)
        for form in SMALL.forms:
            rows = [i for i, s in enumerate(fresh) if s["iron_oxide_form"] == form]
            own = [i for i, s in enumerate(train) if s["iron_oxide_form"] == form]
            np.testing.assert_allclose(preds[rows], np.broadcast_to(R[own].mean(0), (len(rows), len(WL))), atol=1e-8)

    def test_refit_discards_old_state(self):
        train, R, _, _ = exact_cubic_problem(SMALL, 300, seed=3)
        model = SpectralModel(n_components=2).fit(train, R, wavelengths_nm=WL, domain=SMALL)
        model.holdout_scores_ = {"rms": 1.0}
        model.set_params(n_components=3).fit(train, R[:, :8], wavelengths_nm=WL[:8], domain=SMALL)
        assert model.components_.shape == (3, 8) and model.holdout_scores_ is None

    def test_underdetermined_fit_warns(self):
        train, R, _, _ = exact_cubic_problem(SMALL, 60, seed=3)
        with pytest.warns(UserWarning, match="underdetermined"):
            SpectralModel().fit(train, R, wavelengths_nm=WL, domain=SMALL)

    def test_form_without_samples_is_an_error(self):
        train, R, _, _ = exact_cubic_problem(SMALL.restrict(forms=["coating"]), 100, seed=3)
        with pytest.raises(SandlightError, match="particles"):
            SpectralModel().fit(train, R, wavelengths_nm=WL, domain=SMALL)


@pytest.fixture(scope="module")
def three_forms():
    """An exact cubic problem over the three forms, and its model."""
    domain = SMALL.restrict(forms=["coating", "mixed", "particles"])
    train, R, spectra, _ = exact_cubic_problem(domain, 600, seed=3)
    return SpectralModel().fit(train, R, wavelengths_nm=WL, domain=domain), spectra


class TestIronFreeSamples:
    """Without iron oxide the engine builds the same bare sand for every form, but its form
    'coating' jumps at zero (any coating adds its interfaces): an iron-free sample is answered by
    the forms continuous there ('mixed', 'particles'), whatever form it names."""

    def test_every_form_gets_the_mean_of_the_continuous_forms(self, three_forms):
        model, spectra = three_forms
        free = [dict(SMALL.draw(1, seed=5)[0], iron_oxide=0.0, iron_oxide_form=f) for f in model.forms_]
        predicted = model.predict(free)
        np.testing.assert_array_equal(predicted, np.broadcast_to(predicted[0], predicted.shape))
        # The exact cubic per form is continuous: at 10⁻¹² iron oxide each form answers itself.
        near = [dict(s, iron_oxide=1e-12) for s in free]
        own = model.predict(near)
        np.testing.assert_allclose(own, spectra(near), atol=1e-9)
        assert np.abs(own[0] - own[1:].mean(axis=0)).max() > 1e-3  # the forms differ here
        np.testing.assert_allclose(predicted[0], own[1:].mean(axis=0), atol=1e-9)

    def test_a_batch_mixing_iron_free_and_other_rows_keeps_each_row(self, three_forms):
        model, spectra = three_forms
        draws = SMALL.restrict(forms=model.forms_).draw(6, seed=8)
        batch = [dict(s, iron_oxide=0.0) if i % 2 else s for i, s in enumerate(draws)]
        alone = np.vstack([model.predict([s]) for s in batch])
        np.testing.assert_allclose(model.predict(batch), alone, atol=1e-12)
        np.testing.assert_allclose(alone[::2], spectra(batch[::2]), atol=1e-9)

    def test_a_model_with_one_of_those_forms_answers_with_it(self, fitted):
        model, spectra, _ = fitted
        assert model.forms_ == ("coating", "particles")
        free = [dict(SMALL.draw(1, seed=5)[0], iron_oxide=0.0, iron_oxide_form=f) for f in model.forms_]
        np.testing.assert_allclose(model.predict(free), np.broadcast_to(model.predict(free[1:]), (2, len(WL))))
        np.testing.assert_allclose(model.predict(free[1:]), spectra(free[1:]), atol=1e-10)

    def test_a_coating_only_model_answers_as_given(self):
        domain = SMALL.restrict(forms=["coating"])
        train, R, spectra, _ = exact_cubic_problem(domain, 200, seed=3)
        model = SpectralModel().fit(train, R, wavelengths_nm=WL, domain=domain)
        free = [dict(domain.draw(1, seed=5)[0], iron_oxide=0.0)]
        np.testing.assert_allclose(model.predict(free), spectra(free), atol=1e-10)
