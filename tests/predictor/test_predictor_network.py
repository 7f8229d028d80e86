"""The network regressor of SpectralModel: fits what a cubic cannot, round-trips as arrays."""

import numpy as np
import pytest

from sandlight.errors import ModelFileError, ParameterError
from sandlight.predictor import Dimension, Domain, SpectralModel
from sandlight.predictor.network import Network, fit_network

WL = np.arange(400.0, 701.0, 20.0)
#: Two parameters and two forms around the reference sand: small enough to fit in seconds.
TWO = Domain.reference(
    [Dimension("iron_oxide", 0.001, 0.05, "log"), Dimension("hematite_ratio", 0.0, 1.0)], forms=("coating", "particles")
)
SHARP = dict(regressor="network", hidden_units=32, hidden_layers=2, n_components=2, random_state=3)


def sharp_spectra(domain, samples):
    """Spectra with a sigmoid edge in the scaled iron oxide (a cubic leaves ~0.03 of it) whose
    position depends on the hematite ratio and the form."""
    X = np.array([[s[n] for n in domain.names] for s in samples])
    Xs = domain.scaled(X)
    shift = np.array([0.3 if s["iron_oxide_form"] == "particles" else -0.3 for s in samples])
    edge = np.tanh(4 * (Xs[:, 0] - 0.5 * Xs[:, 1] - shift))
    blue, red = np.linspace(1, 0, WL.size), np.linspace(0, 1, WL.size)
    return 0.4 + 0.2 * edge[:, None] * blue + 0.1 * Xs[:, 1:2] * red


@pytest.fixture(scope="module")
def sharp():
    train = TWO.draw(600, seed=1)
    test = TWO.draw(200, seed=2, design="random")
    R = sharp_spectra(TWO, train)
    net = SpectralModel(**SHARP).fit(train, R, wavelengths_nm=WL, domain=TWO)
    cubic = SpectralModel(n_components=2).fit(train, R, wavelengths_nm=WL, domain=TWO)
    return net, cubic, test, sharp_spectra(TWO, test)


def rms(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def test_the_domain_has_the_two_parameters():
    assert TWO.names == ("iron_oxide", "hematite_ratio")


def test_the_network_follows_an_edge_the_cubic_cannot(sharp):
    net, cubic, test, truth = sharp
    cubic_error, net_error = rms(cubic.predict(test), truth), rms(net.predict(test), truth)
    assert cubic_error > 0.015  # the problem is beyond a cubic ...
    assert net_error < cubic_error / 3  # ... and within a network's reach
    assert net.network_.n_inputs == 2 + 2  # the parameters and one indicator per form


def test_a_fit_is_reproducible_from_its_seed():
    train = TWO.draw(200, seed=4)
    R = sharp_spectra(TWO, train)
    a, b = (SpectralModel(**{**SHARP, "hidden_units": 8}).fit(train, R, wavelengths_nm=WL, domain=TWO) for _ in "ab")
    np.testing.assert_array_equal(a.network_.to_arrays()[0], b.network_.to_arrays()[0])


def test_saved_and_loaded_models_predict_the_same(sharp, tmp_path):
    net, _, test, _ = sharp
    loaded = SpectralModel.load(net.save(tmp_path / "net.npz"))
    assert loaded.regressor == "network" and loaded.get_params() == net.get_params()
    np.testing.assert_array_equal(loaded.predict(test), net.predict(test))


def test_a_file_with_the_other_regression_is_refused(sharp, tmp_path):
    net, cubic, _, _ = sharp
    path = net.save(tmp_path / "net.npz")
    meta, arrays = SpectralModel._model_file.read(path)
    # The network's metadata with a cubic's arrays: neither regression is complete.
    mixed = {**{k: v for k, v in arrays.items() if not k.startswith("network")}, "powers": cubic.powers_, "W": cubic.W_}
    SpectralModel._model_file.write(tmp_path / "mixed.npz", {k: v for k, v in meta.items() if "format" not in k}, mixed)
    with pytest.raises(ModelFileError, match="network_parameters"):
        SpectralModel.load(tmp_path / "mixed.npz")


def test_network_arrays_must_chain():
    rng = np.random.default_rng(0)
    net = fit_network(rng.random((40, 3)), rng.random((40, 2)), hidden_units=4, hidden_layers=2, alpha=0.0,
                      ensemble=2, random_state=0)  # fmt: skip
    parameters, shapes = net.to_arrays()
    assert shapes.shape == (2, 3, 2) and parameters.size == net.n_parameters
    again = Network.from_arrays(parameters, shapes)
    x = rng.random((5, 3))
    np.testing.assert_array_equal(again(x), net(x))
    broken = shapes.copy()
    broken[0, 1, 0] = 5
    with pytest.raises(ValueError, match="do not chain"):
        Network.from_arrays(parameters, broken)
    with pytest.raises(ValueError, match="parameters of shape"):
        Network.from_arrays(parameters[:-1], shapes)


def test_a_later_stage_keeps_the_weights_unless_it_improves_them():
    # A second stage at a rate too small to move any weight cannot improve the validation score,
    # so the staged fit returns the one-stage fit's weights bit for bit; a real second stage moves them.
    rng = np.random.default_rng(1)
    X, T = rng.random((120, 3)), rng.random((120, 2))
    settings = dict(hidden_units=8, hidden_layers=2, alpha=0.0, ensemble=1, random_state=0)
    one = fit_network(X, T, **settings).to_arrays()[0]
    frozen = fit_network(X, T, **settings, learning_rates=(1e-3, 1e-30)).to_arrays()[0]
    stepped = fit_network(X, T, **settings, learning_rates=(1e-3, 1e-4)).to_arrays()[0]
    np.testing.assert_array_equal(frozen, one)
    assert not np.array_equal(stepped, one)


def test_a_stepped_rate_fits_the_edge_closer(sharp, tmp_path):
    # What the stages are for (docs/spectral-predictor.md, "Full range"): from the best weights of
    # one rate, a lower rate settles deeper in the same valley.
    net, _, test, truth = sharp
    train = TWO.draw(600, seed=1)
    stepped = SpectralModel(**SHARP, learning_rates=(1e-3, 1e-4)).fit(
        train, sharp_spectra(TWO, train), wavelengths_nm=WL, domain=TWO
    )
    assert rms(stepped.predict(test), truth) < rms(net.predict(test), truth)
    loaded = SpectralModel.load(stepped.save(tmp_path / "stepped.npz"))
    assert loaded.get_params() == stepped.get_params() and loaded.learning_rates == (1e-3, 1e-4)


def test_stopping_on_the_error_is_not_stopped_by_a_noisy_output():
    # Early stopping on R² averaged with equal weight per output (scikit-learn's) is decided by
    # an output that is noise (its R² never improves) and ends the fit before the signal is
    # learnt; stopping on the error of all outputs together follows the signal, which carries
    # nearly all of the variance (the noisy minor scores of a PCA, docs/spectral-predictor.md).
    rng = np.random.default_rng(1)
    X, X_test = rng.uniform(-1, 1, (400, 2)), rng.uniform(-1, 1, (400, 2))

    def f(X):
        return np.tanh(3 * X[:, 0] * X[:, 1]) + np.sin(3 * X[:, 0])

    T = np.column_stack([f(X), 0.05 * rng.standard_normal(400)])
    settings = dict(hidden_units=16, hidden_layers=2, alpha=0.0, ensemble=1, random_state=1)
    error = {
        v: rms(fit_network(X, T, **settings, validation=v)(X_test, "double")[:, 0], f(X_test)) for v in ("r2", "error")
    }
    assert error["error"] < 0.05 < 0.3 < error["r2"]
    with pytest.raises(ParameterError, match="validation"):
        fit_network(X, T, **settings, validation="mse")


def test_the_stopping_score_is_kept_in_the_model_file(sharp, tmp_path):
    train = TWO.draw(600, seed=1)
    model = SpectralModel(**SHARP, network_validation="error").fit(
        train, sharp_spectra(TWO, train), wavelengths_nm=WL, domain=TWO
    )
    loaded = SpectralModel.load(model.save(tmp_path / "error.npz"))
    assert loaded.network_validation == "error" and loaded.get_params() == model.get_params()
    np.testing.assert_array_equal(loaded.predict(sharp[2]), model.predict(sharp[2]))


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("hidden_layers", 0),
        ("hidden_units", 2000),
        ("ensemble", 0),
        ("regressor", "forest"),
        ("learning_rates", ()),
        ("learning_rates", (1e-3, 0.0)),
        ("learning_rates", 1e-3),
        ("network_validation", "mse"),
    ],
)
def test_bad_hyper_parameters_are_refused_by_name(name, value):
    with pytest.raises(ParameterError, match=name):
        SpectralModel(**{name: value}).validate_params()


def test_double_precision_differentiates_where_single_cannot(sharp):
    """A fit's Jacobian is a difference quotient over a step of ~10⁻⁸: in double precision it
    equals the slope over a hundred times that step; both precisions give the same values."""
    net = sharp[0]
    x = np.array([[0.01, 0.4]])
    step = np.array([[1e-8, 0.0]])

    def double(x):
        return net.predict(x, ["coating"], precision="double")

    fine = (double(x + step) - double(x)) / 1e-8
    coarse = (double(x + 1e2 * step) - double(x)) / 1e-6
    np.testing.assert_allclose(fine, coarse, rtol=1e-3, atol=1e-3 * np.abs(coarse).max())
    np.testing.assert_allclose(net.predict(x, ["coating"]), double(x), atol=1e-5)
    with pytest.raises(ParameterError, match="precision"):
        net.predict(x, ["coating"], precision="half")
