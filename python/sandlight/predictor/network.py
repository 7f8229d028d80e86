"""A small neural network that regresses principal-component scores, kept as plain arrays.

The paper's regression (§3.1.2) is a cubic in the sample parameters. Over a few parameters it
is accurate; over all of them (the broad models) its error is the cubic's, not Monte Carlo
noise: on the 10 000 dry samples of every parameter of ``broad-dry`` the cubic leaves 0.030 RMS
on the hold-out set, one network of two tanh layers of 128 units 0.014, four averaged 0.012,
four of three layers stopped on the error 0.011 (scripts/studies/broad_regressors.py;
docs/spectral-predictor.md, "Broad models").

The networks are fitted by scikit-learn's ``MLPRegressor`` (Adam, squared error with an L2
penalty, early stopping on a held-back tenth: on the outputs' mean R² or on their squared error
together, ``fit_network(validation=...)``), optionally in stages of falling learning rate, each
continuing from the best weights of the one before (a step schedule: Adam at a fixed rate stops
where its steps are as large as the valley it is in; the broad and full-range models use three
stages, docs/spectral-predictor.md, "Broad models" and "Full range"), and kept as their weights
and biases only, so that a model file holds plain arrays (never a pickle) and prediction is
numpy: tanh hidden layers and a linear output, h ← tanh(h W + b), in single precision (twice
the batched speed of double in benchmarks/predict.py; the outputs differ by < 10⁻⁵, a
thousandth of the models' errors). An ensemble of networks fitted from different seeds is
averaged (its spread is the part of the error that depends on the seed).

Public objects
--------------
Network
    One or several networks (an ensemble) as arrays: evaluation, and conversion to and from
    the two arrays of a model file.
fit_network
    Fit an ensemble with scikit-learn.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sandlight.checks import check_choice

__all__ = ["VALIDATIONS", "Network", "fit_network"]

#: What a fit's early stopping can follow (`fit_network`'s ``validation``).
VALIDATIONS = ("r2", "error")


@dataclass(frozen=True)
class Network:
    """An ensemble of fully connected networks, tanh hidden layers and a linear output.

    Attributes
    ----------
    layers : tuple of tuple of (weights, bias)
        Per network, its layers in order: weights (n_in, n_out) and bias (n_out,).
    """

    layers: tuple[tuple[tuple[np.ndarray, np.ndarray], ...], ...]

    def __post_init__(self) -> None:
        single = tuple(tuple((w.astype(np.float32), b.astype(np.float32)) for w, b in net) for net in self.layers)
        object.__setattr__(self, "_single", single)

    @property
    def n_inputs(self) -> int:
        return self.layers[0][0][0].shape[0]

    @property
    def n_outputs(self) -> int:
        return self.layers[0][-1][0].shape[1]

    @property
    def n_parameters(self) -> int:
        return sum(w.size + b.size for net in self.layers for w, b in net)

    def __call__(self, X: np.ndarray, precision: str = "single") -> np.ndarray:
        """The ensemble's mean output for inputs ``X`` (n, n_inputs): (n, n_outputs), evaluated
        in ``precision`` ('single' or 'double'). Finite differences need 'double': in single
        precision the outputs move in steps of ~10⁻⁷, so a difference quotient over a small
        step is rounding noise."""
        dtype, nets = (np.float64, self.layers) if precision == "double" else (np.float32, self._single)
        X = np.asarray(X, dtype=dtype)
        out = np.zeros((X.shape[0], self.n_outputs), dtype=dtype)
        for net in nets:
            h = X
            for w, b in net[:-1]:
                h = h @ w
                h += b
                np.tanh(h, out=h)
            w, b = net[-1]
            out += h @ w + b
        return out.astype(float) / len(self._single)

    def to_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(parameters, shapes): every weight matrix and bias flattened in order into one float
        array, and an int array (n_networks, n_layers, 2) of the weight matrices' shapes."""
        flat = [a.ravel() for net in self.layers for w, b in net for a in (w, b)]
        shapes = np.array([[w.shape for w, _ in net] for net in self.layers], dtype=np.int64)
        return np.concatenate(flat), shapes

    @classmethod
    def from_arrays(cls, parameters: np.ndarray, shapes: np.ndarray) -> Network:
        """The inverse of :meth:`to_arrays`, checking that the arrays fit together.

        Raises
        ------
        ValueError
            Shapes that do not chain (a layer's inputs are not the previous one's outputs, the
            networks differ in inputs or outputs) or a parameter count that does not match.
        """
        shapes = np.asarray(shapes)
        if shapes.ndim != 3 or shapes.shape[2] != 2 or shapes.shape[0] < 1 or shapes.shape[1] < 1:
            raise ValueError(f"network shapes of shape {shapes.shape}, expected (networks, layers, 2)")
        if (shapes < 1).any():
            raise ValueError("network layers need at least one input and one output")
        if (shapes[:, 1:, 0] != shapes[:, :-1, 1]).any():
            raise ValueError("network layers do not chain: a layer's inputs differ from the outputs before it")
        if (shapes[:, 0, 0] != shapes[0, 0, 0]).any() or (shapes[:, -1, 1] != shapes[0, -1, 1]).any():
            raise ValueError("the networks of an ensemble differ in inputs or outputs")
        needed = int(sum(i * o + o for i, o in shapes.reshape(-1, 2)))
        if parameters.shape != (needed,):
            raise ValueError(f"network parameters of shape {parameters.shape}, expected ({needed},)")
        layers, at = [], 0
        for net in shapes:
            layer = []
            for i, o in net:
                w = parameters[at : at + i * o].reshape(i, o)
                b = parameters[at + i * o : at + i * o + o]
                layer.append((w, b))
                at += i * o + o
            layers.append(tuple(layer))
        return cls(tuple(layers))


def fit_network(
    X: np.ndarray,
    T: np.ndarray,
    *,
    hidden_units: int,
    hidden_layers: int,
    alpha: float,
    ensemble: int,
    random_state: int,
    learning_rates: tuple[float, ...] = (1e-3,),
    validation: str = "r2",
) -> Network:
    """Fit ``ensemble`` networks T ≈ f(X) with scikit-learn's MLPRegressor and keep their arrays.

    Parameters
    ----------
    X : ndarray (n, n_inputs)
        Inputs, scaled to about [−1, 1].
    T : ndarray (n, n_outputs)
        Targets, of order 1.
    hidden_units, hidden_layers : int
        Width and number of the tanh hidden layers.
    alpha : float
        L2 penalty of MLPRegressor.
    ensemble : int
        Networks fitted from seeds ``random_state``, ``random_state + 1``, ... and averaged.
    random_state : int
        Seed of the first network's initial weights, batches and validation split.
    learning_rates : tuple of float
        Adam's learning rate of each stage (> 0): the first from the initial weights, each later
        one from the best weights so far, on the same validation split; a stage ends when the
        validation score has not improved for 60 epochs, and only an improvement replaces the
        weights kept.
    validation : {"r2", "error"}
        The validation score that early stopping follows: "r2", scikit-learn's R² averaged
        over the outputs with equal weight, or "error", the R² of all outputs together,
        1 − Σ squared error / Σ variance, which falls as the squared error of T does (for
        principal-component scores under one scale, the reflectance's: minor, noisy scores,
        whose R² stays low, then no longer decide when the fit stops).
    """
    import warnings

    check_choice("validation", validation, VALIDATIONS)
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.neural_network import MLPRegressor

    class ErrorStoppedMLP(MLPRegressor):
        # Early stopping scores the validation split with `_score` (scikit-learn's private
        # hook, R² with equal weight per output); variance-weighted R² is 1 − SSE/SST over all
        # outputs at once.
        def _score(self, X: np.ndarray, y: np.ndarray, sample_weight: np.ndarray | None = None) -> float:
            return self._score_with_function(X, y, sample_weight, _variance_weighted_r2)

    regressor = ErrorStoppedMLP if validation == "error" else MLPRegressor
    layers = []
    for member in range(ensemble):
        mlp = regressor(
            hidden_layer_sizes=(hidden_units,) * hidden_layers,
            activation="tanh",
            solver="adam",
            alpha=alpha,
            batch_size=min(128, max(1, int(0.9 * X.shape[0]))),  # what early stopping leaves to train on
            learning_rate_init=learning_rates[0],
            max_iter=2000,
            tol=1e-7,
            early_stopping=True,
            validation_fraction=0.1,
            n_iter_no_change=60,
            random_state=random_state + member,
            warm_start=True,  # a later stage starts from the weights the one before kept
        )
        for stage, rate in enumerate(learning_rates):
            if stage:
                # A fresh Adam at the new rate; the patience counter is scikit-learn's private
                # state, which warm_start carries over (it ended the stage before), so reset it.
                mlp.set_params(learning_rate_init=rate)
                mlp._no_improvement_count = 0
            with warnings.catch_warnings():
                # Stopping at max_iter still leaves the best weights seen; the hold-out set judges them.
                warnings.simplefilter("ignore", ConvergenceWarning)
                mlp.fit(X, T if T.shape[1] > 1 else T[:, 0])
        layers.append(tuple((np.asarray(w, float), np.asarray(b, float)) for w, b in zip(mlp.coefs_, mlp.intercepts_)))
    return Network(tuple(layers))


def _variance_weighted_r2(y: np.ndarray, prediction: np.ndarray, sample_weight: np.ndarray | None = None) -> float:
    """1 − Σ squared error / Σ variance over all outputs (scikit-learn's variance-weighted R²)."""
    from sklearn.metrics import r2_score

    return float(r2_score(y, prediction, sample_weight=sample_weight, multioutput="variance_weighted"))
