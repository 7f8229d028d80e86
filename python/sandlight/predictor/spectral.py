"""The spectral predictor: reflectance of a sand sample from its parameters (paper §3.1).

Monte Carlo reflectance curves of a training set are compressed by principal component analysis
(§3.1.1, eq. 2: r ≈ r̄ + U_k r̃), and the k principal components are regressed on cubic
monomials of the scaled sample parameters (§3.1.2, eq. 3: r̃ ≈ Wᵀ φ(x)). Together (eq. 4, with
the mean that the paper's eq. 2 leaves implicit):

    r(x) ≈ r̄ + U_k Wᵀ φ(x)

Public objects
--------------
SpectralModel
    The estimator (scikit-learn conventions: hyper-parameters in ``__init__``, learned attributes
    ending in ``_``).
evaluate, HoldoutReport
    Error of a model against Monte Carlo hold-out samples, per wavelength, next to the Monte
    Carlo noise of those samples.
MODEL_FILE
    The model-file format (:mod:`sandlight.predictor.model_file`).

The iron-oxide form (categorical) is handled either by one regression per form
(``forms="separate"``, the default: W has one slice per form, the PCA basis is shared) or by
one-hot indicator inputs (``forms="onehot"``: one W, the indicators enter the monomials).

Where the cubic is too stiff (every parameter at once: the broad models), ``regressor="network"``
replaces φ and W by a small neural network of the scaled parameters and one-hot form indicators
(:mod:`sandlight.predictor.network`): r(x) ≈ r̄ + U_k s·f(x), s one scale of the scores.

References
----------
"Simulating the Appearance of Sandy Landscapes", §3.1 (the paper sandlight implements); the
training data come from sandlight's SPLITS-like transport engine instead of SPLITS.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from numbers import Integral, Real
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from sandlight.checks import Interval, Names, Numbers, StrOptions
from sandlight.errors import ParameterError, SandlightError
from sandlight.predictor.domain import FORM_PARAMETER, Domain, at_fixed_value
from sandlight.predictor.estimator import Estimator
from sandlight.predictor.model_file import ModelFileFormat, jsonable
from sandlight.predictor.monomials import BLOCK_SAMPLES, monomial_plan, monomials
from sandlight.predictor.network import VALIDATIONS, Network, fit_network
from sandlight.predictor.pca import n_components_for, principal_directions, signal_variance_ratio, variance_ratio
from sandlight.predictor.physical_inputs import PHYSICAL_INPUTS, physical_inputs
from sandlight.predictor.samples import sample_columns

if TYPE_CHECKING:
    import xarray as xr

#: The forms whose reflectance is continuous at zero iron oxide. Without iron oxide every form is
#: the same bare sand (the engine builds no coating, no pigment and clear cores), but the
#: engine's reflectance for the form 'coating' jumps there: a coating of any thickness adds its
#: interfaces to every grain (+0.027 at 400 nm for ottawa-quartz at 10⁻⁹ iron oxide). So a
#: model's 'coating' near zero answers for that coated skin, and an iron-free sample is answered
#: by the mean of these forms' predictions instead (docs/spectral-predictor.md, "Broad models").
IRON_FREE_FORMS = ("mixed", "particles")

_ARRAYS = (
    "wavelengths_nm",
    "mean",
    "components",
    "explained_variance_ratio",
    "scale_center",
    "scale_halfwidth",
)
#: The regression's arrays: the monomials' exponents and coefficients, or the network's.
_MONOMIAL_ARRAYS = ("powers", "W")
_NETWORK_ARRAYS = ("network_parameters", "network_shapes", "network_output_scale")
#: The scaling of a network's physical inputs (only with ``physical_inputs``).
_PHYSICAL_ARRAYS = ("physical_center", "physical_halfwidth")
#: Version 2: log scales take an offset (Dimension.offset); models carry a name and a
#: description. Version 3: the regression is monomials (powers, W) or a network. Version 4: a
#: network may take physical inputs (params.physical_inputs; physical_center and
#: physical_halfwidth), which a version-3 reader would not know. Format-1 files (sqrt-scaled
#: concentrations, no name) still load.
MODEL_FILE = ModelFileFormat(
    "sandlight-spectral-model",
    4,
    "spectral model",
    _ARRAYS,
    optional=_MONOMIAL_ARRAYS + _NETWORK_ARRAYS + _PHYSICAL_ARRAYS,
)
MODEL_FORMAT, MODEL_FORMAT_VERSION = MODEL_FILE.name, MODEL_FILE.version


# ---- inputs -----------------------------------------------------------------------------------
def _form_codes(forms: ArrayLike | None, n: int, known: tuple[str, ...]) -> np.ndarray:
    """Integer codes (indices into ``known``) of form names or codes, one per sample."""
    if forms is None:
        if len(known) == 1:
            return np.zeros(n, dtype=np.intp)
        raise ParameterError(
            "forms",
            None,
            f"the iron-oxide form of each row, as names or codes into {known} (this model covers several forms)",
        )
    forms = np.asarray(forms)
    if forms.ndim == 0:
        forms = np.full(n, forms[()])
    if forms.shape != (n,):
        raise ParameterError("forms", forms.shape, f"one form per sample: shape ({n},)")
    if forms.dtype.kind in "iu":
        bad = (forms < 0) | (forms >= len(known))
        if bad.any():
            raise ParameterError(
                FORM_PARAMETER, int(forms[np.argmax(bad)]), f"a code in 0..{len(known) - 1} for {known}"
            )
        return forms.astype(np.intp)
    names, inverse = np.unique(forms.astype(str), return_inverse=True)
    codes = np.empty(len(names), dtype=np.intp)
    for i, name in enumerate(names):
        if name not in known:
            raise ParameterError(FORM_PARAMETER, str(name), f"one of {known}, the forms this model was trained on")
        codes[i] = known.index(name)
    return codes[inverse]


# ---- the estimator ----------------------------------------------------------------------------
class SpectralModel(Estimator):
    """Spectral reflectance predictor r(x) ≈ r̄ + U_k Wᵀ φ(x) (paper §3.1, eq. 4).

    Parameters
    ----------
    n_components : int, optional
        Number k of principal components kept. Default: the smallest k whose cumulative
        explained variance reaches ``variance_threshold``.
    variance_threshold : float
        In (0, 1]; used when ``n_components`` is None (paper: 4 components hold > 99.9 %).
    degree : int
        Degree of the monomial features φ (paper: 3, cubic), in 1..4.
    ridge : float
        Ridge penalty λ ≥ 0 on the non-constant coefficients (0: ordinary least squares).
        Parameters are scaled to [−1, 1], so λ is comparable across parameters.
    forms : {"separate", "onehot"}
        How the iron-oxide form enters: one regression per form, or one-hot inputs.
    regressor : {"monomials", "network"}
        The regression of the scores: the paper's monomials φ(x) and W (``degree``, ``ridge``,
        ``forms`` apply), or a neural network of the scaled parameters and one-hot form
        indicators (``hidden_units``, ``hidden_layers``, ``network_alpha``, ``ensemble``,
        ``learning_rates``, ``network_validation``, ``physical_inputs``, ``random_state`` apply;
        :mod:`sandlight.predictor.network`).
    hidden_units, hidden_layers : int
        Width (1–1024) and number (1–4) of the network's tanh hidden layers.
    network_alpha : float
        L2 penalty ≥ 0 of the network's weights (scikit-learn's ``alpha``).
    ensemble : int
        Networks fitted from successive seeds and averaged (1–16).
    learning_rates : sequence of float
        Adam's learning rate of each stage of a network's fit, each > 0 (1–4 stages; later
        stages continue from the best weights of the earlier ones). Default (0.001,): one stage.
    network_validation : {"r2", "error"}
        What early stopping follows on the held-back tenth of the training set: "r2" (default),
        scikit-learn's R² averaged over the k scores with equal weight, or "error", the squared
        error of all scores together, i.e. of the reflectance (one scale for every score), so
        that the minor, noisy scores do not decide when a fit stops.
    physical_inputs : sequence of str
        Lengths of the mass balance the network also takes, scaled like the parameters (names
        of :data:`~sandlight.predictor.physical_inputs.PHYSICAL_INPUTS`: pore mean free path,
        coating and film thickness, water-filled share, iron path inside a grain;
        :mod:`sandlight.predictor.physical_inputs`). Default (): the parameters alone. Network only.
    random_state : int
        Seed of the first network (≥ 0): a fit is reproducible.

    Attributes
    ----------
    wavelengths_ : ndarray (n_wl,)
        Wavelengths, nm.
    domain_ : Domain
        Training domain; inputs outside it are refused unless ``extrapolate=True``.
    parameter_names_ : tuple of str
        Input parameters, in the column order of array input.
    forms_ : tuple of str
        Iron-oxide forms, in the order of integer form codes.
    n_components_ : int
        k.
    mean_ : ndarray (n_wl,)
        Mean training reflectance r̄.
    components_ : ndarray (k, n_wl)
        Principal directions U_kᵀ (orthonormal rows).
    explained_variance_ratio_ : ndarray (min(n, n_wl),)
        Share of the training variance along every principal direction (not only the k kept).
    signal_variance_ratio_ : ndarray (min(n, n_wl),) or None
        The same for the noise-free signal, when the fit was given Monte Carlo standard errors:
        along direction u the noise variance u·diag(⟨σ²⟩)u (⟨σ²⟩ the mean squared standard
        error per wavelength; exact for noise independent between wavelengths) is subtracted
        from the variance (clamped at 0). k is chosen on these ratios. Not saved in files.
    scale_center_, scale_halfwidth_ : ndarray (n_parameters,)
        Feature scaling: x_scaled = (t(x) − center)/halfwidth, t the dimension's scale.
    powers_ : ndarray (m, n_inputs)
        Exponents of the monomials φ (PolynomialFeatures order; for one-hot, the last inputs
        are the indicators of forms_[1:]). Monomials only.
    W_ : ndarray (n_groups, m, k)
        Regression coefficients: one slice per form (separate) or a single one (one-hot).
        Monomials only.
    network_ : Network
        The network (ensemble) f; its outputs times ``network_output_scale_`` are the scores.
        Network only.
    network_output_scale_ : float
        s: the standard deviation of the training scores (the network fits scores / s).
    physical_center_, physical_halfwidth_ : ndarray (len(physical_inputs),)
        Scaling of the physical inputs to [−1, 1] over the training set. With
        ``physical_inputs`` only.
    training_rms_ : float
        RMS of (prediction − training reflectance) over the training set.
    reconstruction_rms_ : float
        RMS error of the rank-k PCA reconstruction of the training set (the floor of the above).
    training_set_ : dict
        Reference to the training data (path, checksum, size, seed, rays, engine settings ...),
        as given.
    memory_ : str
        Path memory of the engine that produced the training set (from ``training_set_``):
        'none', the classic model, unless the training set records another.
    holdout_scores_ : dict or None
        Hold-out scores attached by :func:`evaluate` (``attach=True``).
    name_ : str
        Name of the model (e.g. in a :class:`~sandlight.predictor.bank.ModelBank`); the file
        name without extension for format-1 files.
    description_ : str
        What the model covers, in words (may be empty).

    Examples
    --------
    >>> model = SpectralModel().fit(training_dataset)            # doctest: +SKIP
    >>> model.predict([SandSample.preset("red-dune")])           # doctest: +SKIP
    array([[0.21, 0.22, ...]])
    """

    _parameter_constraints: ClassVar[dict[str, list]] = {
        "n_components": [None, Interval(Integral, 1, None)],
        "variance_threshold": [Interval(Real, 0, 1, closed="right")],
        "degree": [Interval(Integral, 1, 4)],
        "ridge": [Interval(Real, 0, None)],
        "forms": [StrOptions(("separate", "onehot"))],
        "regressor": [StrOptions(("monomials", "network"))],
        "hidden_units": [Interval(Integral, 1, 1024)],
        "hidden_layers": [Interval(Integral, 1, 4)],
        "network_alpha": [Interval(Real, 0, None)],
        "ensemble": [Interval(Integral, 1, 16)],
        "learning_rates": [Numbers(Interval(Real, 0, None, closed="neither"), 1, 4)],
        "network_validation": [StrOptions(VALIDATIONS)],
        "physical_inputs": [Names(PHYSICAL_INPUTS)],
        "random_state": [Interval(Integral, 0, None)],
    }
    _model_file = MODEL_FILE

    def __init__(
        self,
        n_components: int | None = None,
        variance_threshold: float = 0.999,
        degree: int = 3,
        ridge: float = 0.0,
        forms: str = "separate",
        regressor: str = "monomials",
        hidden_units: int = 128,
        hidden_layers: int = 2,
        network_alpha: float = 1e-6,
        ensemble: int = 1,
        learning_rates: tuple[float, ...] = (1e-3,),
        network_validation: str = "r2",
        physical_inputs: tuple[str, ...] = (),
        random_state: int = 0,
    ) -> None:
        self.n_components = n_components
        self.variance_threshold = variance_threshold
        self.degree = degree
        self.ridge = ridge
        self.forms = forms
        self.regressor = regressor
        self.hidden_units = hidden_units
        self.hidden_layers = hidden_layers
        self.network_alpha = network_alpha
        self.ensemble = ensemble
        self.learning_rates = learning_rates
        self.network_validation = network_validation
        self.physical_inputs = physical_inputs
        self.random_state = random_state

    # -- inputs -------------------------------------------------------------------------------
    def _inputs(
        self, X: Any, forms: Any, domain: Domain, known_forms: tuple[str, ...], extrapolate: bool
    ) -> tuple[np.ndarray, np.ndarray]:
        """(values (n, d) raw, form codes (n,)) from any supported input, checked."""
        names = domain.names
        if isinstance(X, np.ndarray) and X.dtype.names is None and X.dtype.kind in "fiu":
            values = np.asarray(X, dtype=float)
            if values.ndim == 1:
                values = values[None, :]
            if values.ndim != 2 or values.shape[1] != len(names):
                raise ParameterError("X", values.shape, f"(n, {len(names)}) with columns {names}")
            codes = _form_codes(forms, values.shape[0], known_forms)
        else:
            if forms is not None:
                raise ParameterError(
                    "forms", forms, f"None for named samples: they give {FORM_PARAMETER} (or take its default)"
                )
            columns = sample_columns(X)  # parameters not given take SandSample's defaults
            values = np.column_stack([columns[n] for n in names])
            codes = _form_codes(columns[FORM_PARAMETER], values.shape[0], known_forms)
            if not extrapolate:
                for name, fixed in domain.fixed.items():
                    bad = ~at_fixed_value(columns[name], fixed)
                    if bad.any():
                        raise ParameterError(
                            name,
                            float(columns[name][np.argmax(bad)]),
                            f"{fixed:g}, the value it was fixed at in the training domain "
                            f"(pass extrapolate=True to ignore it)",
                        )
        domain.check(values, extrapolate=extrapolate)
        return values, codes

    def _design(self, values: np.ndarray, codes: np.ndarray, domain: Domain) -> np.ndarray:
        """Inputs of the regression: scaled parameters, plus form indicators for one-hot
        monomials (forms 1.. : form 0 is the constant) or a network (every form), plus the
        scaled physical inputs of a network that takes them."""
        Xs = domain.scaled(values)
        n_forms = len(domain.forms)
        if n_forms > 1 and (self.regressor == "network" or self.forms == "onehot"):
            first = 0 if self.regressor == "network" else 1
            indicators = (codes[:, None] == np.arange(first, n_forms)[None, :]).astype(float)
            Xs = np.hstack([Xs, indicators])
        if self.physical_inputs:
            lengths = physical_inputs(values, codes, domain, tuple(self.physical_inputs))
            Xs = np.hstack([Xs, (lengths - self.physical_center_) / self.physical_halfwidth_])
        return Xs

    # -- fitting ------------------------------------------------------------------------------
    def fit(
        self,
        X: Any,
        R: Any = None,
        *,
        stderr: Any = None,
        wavelengths_nm: Any = None,
        domain: Domain | None = None,
        forms: Any = None,
        training_set: Mapping | None = None,
        name: str = "spectral",
        description: str = "",
    ) -> SpectralModel:
        """Fit the PCA basis and the regression.

        Parameters
        ----------
        X : xarray.Dataset, list of SandSample or dict, structured array, DataFrame, or array
            Training samples. A training-set dataset (:func:`generate_training_set`) also gives
            ``R``, the wavelengths, the domain and the training-set reference.
        R : array_like (n, n_wl), optional
            Reflectance of each sample (fraction, [0, 1]).
        stderr : array_like (n, n_wl), optional
            Monte Carlo standard errors of R. When given, the number of components is chosen
            on the signal variance (see ``signal_variance_ratio_``).
        wavelengths_nm : array_like (n_wl,), optional
            Wavelengths of the columns of R, nm.
        domain : Domain, optional
            Training domain (default: the dataset's, else ``Domain.default()``).
        forms : array_like, optional
            Form names or codes when X is a plain float array.
        training_set : mapping, optional
            Reference to the training data, kept in ``training_set_`` and in saved files.
        name, description : str
            Kept in ``name_`` and ``description_`` (and in saved files).

        Returns
        -------
        self
        """
        self.validate_params()
        if self.physical_inputs and self.regressor != "network":
            raise ParameterError(
                "physical_inputs", self.physical_inputs, "() unless regressor='network' (monomials take the parameters)"
            )
        data = self._training_data(X, R, stderr, wavelengths_nm, domain, forms)
        mean, components, ratio, signal_ratio = self._principal_components(data.R, data.stderr)
        scores = (data.R - mean) @ components.T  # principal components r̃ of each sample (eq. 2)
        if self.physical_inputs:
            lengths = physical_inputs(data.values, data.codes, data.domain, tuple(self.physical_inputs))
            low, high = lengths.min(axis=0), lengths.max(axis=0)
            self.physical_center_ = 0.5 * (low + high)
            self.physical_halfwidth_ = np.where(high > low, 0.5 * (high - low), 1.0)  # 1: constant here (dry)
        Xs = self._design(data.values, data.codes, data.domain)
        if self.regressor == "network":
            # One scale for every score keeps the squared error that of the reflectance
            # (orthonormal components) while giving the optimiser targets of order 1.
            scale = float(scores.std()) or 1.0
            self.network_ = fit_network(
                Xs,
                scores / scale,
                hidden_units=self.hidden_units,
                hidden_layers=self.hidden_layers,
                alpha=self.network_alpha,
                ensemble=self.ensemble,
                random_state=self.random_state,
                learning_rates=tuple(self.learning_rates),
                validation=self.network_validation,
            )
            self.network_output_scale_ = scale
        else:
            Phi, powers = self._monomial_features(Xs)
            self.powers_ = powers
            self.W_ = self._solve(Phi, scores, data.codes, data.domain.forms)
            self._plan = monomial_plan(self.powers_)

        self.wavelengths_ = data.wavelengths
        self.domain_ = data.domain
        self.parameter_names_ = data.domain.names
        self.forms_ = tuple(data.domain.forms)
        self.n_features_in_ = len(data.domain.names)
        self.n_components_ = components.shape[0]
        self.mean_ = mean
        self.components_ = components
        self.explained_variance_ratio_ = ratio
        self.signal_variance_ratio_ = signal_ratio
        self.scale_center_, self.scale_halfwidth_ = data.domain.scaling()
        self.training_set_ = {**data.info, **dict(training_set or {})}
        self.holdout_scores_ = None
        self.name_, self.description_ = str(name), str(description)
        self.training_rms_, self.reconstruction_rms_ = self._training_errors(Xs, data.codes, data.R, scores)
        return self

    def _training_data(
        self, X: Any, R: Any, stderr: Any, wavelengths_nm: Any, domain: Domain | None, forms: Any
    ) -> _TrainingData:
        """The arguments of :meth:`fit`, taken from a training-set dataset where not given, checked."""
        info = {}
        if hasattr(X, "data_vars") and "reflectance" in X.data_vars:
            if R is None:
                R = X["reflectance"].values
                if stderr is None and "stderr" in X.data_vars:
                    stderr = X["stderr"].values
            if wavelengths_nm is None and "wavelength" in X.coords:
                wavelengths_nm = X["wavelength"].values
            if domain is None and "domain" in X.attrs:
                domain = Domain.from_dict(json.loads(X.attrs["domain"]))
            info = {
                k: jsonable(X.attrs[k])
                for k in ("n_samples", "seed", "rays", "design", "sandlight_version", "simulator")
                if k in X.attrs
            }
            if "engine" in X.attrs:
                info["engine"] = json.loads(X.attrs["engine"])
        domain = Domain.default() if domain is None else domain
        if R is None:
            raise ParameterError("R", None, "the reflectance of each training sample, shape (n, n_wavelengths)")
        R = np.asarray(R, dtype=float)
        if R.ndim != 2 or not np.isfinite(R).all():
            raise ParameterError("R", R.shape, "a finite (n, n_wavelengths) array")
        if stderr is not None:
            stderr = np.asarray(stderr, dtype=float)
            if stderr.shape != R.shape or not (np.isfinite(stderr) & (stderr >= 0)).all():
                raise ParameterError("stderr", stderr.shape, f"finite values >= 0 of the shape of R {R.shape}")
        if wavelengths_nm is None:
            raise ParameterError("wavelengths_nm", None, f"{R.shape[1]} wavelengths in nm")
        wavelengths = np.asarray(wavelengths_nm, dtype=float)
        if wavelengths.shape != (R.shape[1],):
            raise ParameterError("wavelengths_nm", wavelengths.shape, f"({R.shape[1]},), one per column of R")
        values, codes = self._inputs(X, forms, domain, domain.forms, extrapolate=False)
        if values.shape[0] != R.shape[0]:
            raise ParameterError("R", R.shape, f"one row per sample ({values.shape[0]})")
        return _TrainingData(values, codes, R, stderr, wavelengths, domain, info)

    def _principal_components(
        self, R: np.ndarray, stderr: np.ndarray | None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
        """PCA (paper §3.1.1) of the training spectra: mean r̄, the k kept directions U_kᵀ, the
        explained and (with ``stderr``) signal variance ratios."""
        mean = R.mean(axis=0)
        variance, directions = principal_directions(R - mean)
        ratio = variance_ratio(variance)
        signal_ratio = None
        if stderr is not None:
            # Variance of Monte Carlo noise along direction u: Σ_λ u_λ² ⟨σ²_λ⟩, ⟨σ²⟩ the mean
            # squared standard error per wavelength (exact for noise independent between them).
            signal_ratio = signal_variance_ratio(variance, (directions**2) @ np.mean(stderr**2, axis=0))
        if self.n_components is None:
            # Monte Carlo noise spreads over all directions; with stderr given, k is chosen on
            # the noise-free (signal) variance so that noise does not inflate k.
            chosen = ratio if signal_ratio is None else signal_ratio
            k = n_components_for(chosen, self.variance_threshold, len(ratio))
        else:
            k = int(self.n_components)
            if k > len(ratio):
                raise ParameterError("n_components", k, f"<= min(n_samples, n_wavelengths) = {len(ratio)}")
        return mean, directions[:k], ratio, signal_ratio

    def _monomial_features(self, Xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """φ(x), the monomials of degree <= ``degree`` of the design (paper §3.1.2), and their
        exponents (PolynomialFeatures order)."""
        from sklearn.preprocessing import PolynomialFeatures

        poly = PolynomialFeatures(degree=self.degree, include_bias=True).fit(Xs)
        return poly.transform(Xs), poly.powers_.astype(np.int64)

    def _solve(self, Phi: np.ndarray, scores: np.ndarray, codes: np.ndarray, known: tuple[str, ...]) -> np.ndarray:
        """Regression (paper §3.1.2, eq. 3) r̃ ≈ Wᵀ φ(x): W (groups, m, k), one slice per form
        (``forms="separate"``) or one for all (``"onehot"``)."""
        n, m = Phi.shape
        groups = range(len(known)) if self.forms == "separate" else [None]
        W = np.empty((len(groups), m, scores.shape[1]))
        for g in groups:
            rows = slice(None) if g is None else codes == g
            n_rows = n if g is None else int(rows.sum())
            if n_rows == 0:
                raise SandlightError(
                    f"no training sample has {FORM_PARAMETER} = {known[g]!r}; "
                    f"restrict the domain's forms or add samples"
                )
            if n_rows < m and self.ridge == 0:
                warnings.warn(
                    f"{n_rows} training samples for {m} monomial features"
                    f"{'' if g is None else f' (form {known[g]})'}: the least-squares "
                    f"problem is underdetermined; add samples or set ridge > 0",
                    stacklevel=3,
                )
            W[0 if g is None else g] = _least_squares(Phi[rows], scores[rows], self.ridge)
        return W

    def _training_errors(
        self, Xs: np.ndarray, codes: np.ndarray, R: np.ndarray, scores: np.ndarray
    ) -> tuple[float, float]:
        """RMS errors over the training set of the fitted model and of the rank-k PCA
        reconstruction (the floor of the former)."""
        residual = self._evaluate(Xs, codes) - R
        recon = self.mean_ + scores @ self.components_
        return float(np.sqrt(np.mean(residual**2))), float(np.sqrt(np.mean((recon - R) ** 2)))

    # -- prediction ---------------------------------------------------------------------------
    def predict(
        self, samples: Any, forms: Any = None, *, extrapolate: bool = False, precision: str = "single"
    ) -> np.ndarray:
        """Predicted directional-hemispherical reflectance at normal incidence.

        Parameters
        ----------
        samples : SandSample, list of SandSample or dict, dict of columns, structured array,
                  DataFrame, xarray.Dataset, or float array (n, n_parameters)
            The samples. Named ones follow :func:`sandlight.predictor.samples.sample_columns`
            (scalars hold for every sample; parameters not given take SandSample's defaults,
            which must then lie in the training domain). A plain float array has the columns
            ``parameter_names_`` (raw units, e.g. grain_size in mm) and needs ``forms`` unless
            the model has a single form.
        forms : array_like of str or int, or str, optional
            Iron-oxide form of each row of a plain array: names, or codes into ``forms_``
            (named samples give theirs).
        extrapolate : bool
            Evaluate inputs outside the training domain (the polynomial is then unreliable)
            instead of raising; fixed parameters of the domain (e.g. depth_mm) are then ignored.
        precision : {'single', 'double'}
            Arithmetic of a network regressor (monomials are always double): 'single' is twice
            as fast in batches; 'double' is what finite differences (a fit's Jacobian) need.

        Returns
        -------
        ndarray (n_samples, n_wavelengths)
            Reflectance (fraction) at ``wavelengths_``; one row even for a single sample.

        Raises
        ------
        ParameterError
            An input outside the training domain (naming the parameter, its value and the
            range) unless ``extrapolate``; NaN, an unknown form, or input that can be read more
            than one way (arrays of different lengths, 2-D arrays) always.
        """
        self.check_is_fitted()
        if precision not in ("single", "double"):
            raise ParameterError("precision", precision, "'single' or 'double'")
        values, codes = self._inputs(samples, forms, self.domain_, self.forms_, extrapolate)
        iron_oxide = self._iron_oxide(values)
        free = np.flatnonzero(iron_oxide == 0.0)
        continuous = [self.forms_.index(f) for f in IRON_FREE_FORMS if f in self.forms_]
        if not (free.size and continuous):
            return self._evaluate(self._design(values, codes, self.domain_), codes, precision)
        # One batch: the other rows with their own forms, the iron-free rows once per continuous form.
        kept = np.flatnonzero(iron_oxide != 0.0)  # NaN (no iron-oxide column) keeps its own form
        rows = np.concatenate([values[kept], *([values[free]] * len(continuous))])
        row_forms = np.concatenate([codes[kept], *(np.full(free.size, c, dtype=codes.dtype) for c in continuous)])
        answers = self._evaluate(self._design(rows, row_forms, self.domain_), row_forms, precision)
        out = np.empty((values.shape[0], answers.shape[1]), dtype=answers.dtype)
        out[kept] = answers[: kept.size]
        out[free] = answers[kept.size :].reshape(len(continuous), free.size, -1).mean(axis=0)
        return out

    def _iron_oxide(self, values: np.ndarray) -> np.ndarray:
        """The iron oxide of each row: its column, or the value the domain fixes."""
        if "iron_oxide" in self.domain_.names:
            return values[:, self.domain_.names.index("iron_oxide")]
        return np.full(values.shape[0], float(self.domain_.fixed.get("iron_oxide", np.nan)))

    def _evaluate(self, Xs: np.ndarray, codes: np.ndarray, precision: str = "single") -> np.ndarray:
        """r̄ + U_k Wᵀ φ(x) for scaled inputs, blockwise (see :mod:`sandlight.predictor.monomials`),
        or r̄ + U_k s·f(x) for a network."""
        if self.regressor == "network":
            out = np.empty((Xs.shape[0], len(self.wavelengths_)))
            for start in range(0, Xs.shape[0], BLOCK_SAMPLES):
                block = out[start : start + BLOCK_SAMPLES]
                scores = self.network_(Xs[start : start + BLOCK_SAMPLES], precision) * self.network_output_scale_
                np.matmul(scores, self.components_, out=block)
                block += self.mean_
            return out
        n = Xs.shape[0]
        m, k = self.W_.shape[1:]
        out = np.empty((n, len(self.wavelengths_)))
        if self.W_.shape[0] == 1 or n == 0 or (codes == codes[0]).all():
            groups = [(0 if self.W_.shape[0] == 1 else int(codes[0] if n else 0), 0, n)]
            order = None
        else:  # sort by form once, so that each form's rows are one contiguous range
            order = np.argsort(codes, kind="stable")
            Xs = Xs[order]
            counts = np.bincount(codes, minlength=self.W_.shape[0])
            bounds = np.concatenate([[0], np.cumsum(counts)])
            groups = [(g, bounds[g], bounds[g + 1]) for g in range(len(counts)) if counts[g]]
        result = out if order is None else np.empty_like(out)
        buffer = np.empty((m, min(BLOCK_SAMPLES, max(n, 1))))
        scores = np.empty((min(BLOCK_SAMPLES, max(n, 1)), k))
        for g, lo, hi in groups:
            W = self.W_[g]
            for start in range(lo, hi, BLOCK_SAMPLES):
                stop = min(start + BLOCK_SAMPLES, hi)
                XT = np.ascontiguousarray(Xs[start:stop].T)
                F = monomials(XT, self._plan, m, buffer)
                T = np.matmul(F.T, W, out=scores[: stop - start])  # r̃ = Wᵀ φ(x)   (eq. 3)
                block = result[start:stop]
                np.matmul(T, self.components_, out=block)  # U_k r̃        (eq. 2)
                block += self.mean_
        if order is not None:
            out[order] = result
        return out

    @property
    def memory_(self) -> str:
        return (self.training_set_.get("engine") or {}).get("memory", "none")

    # -- persistence --------------------------------------------------------------------------
    def _metadata(self) -> dict[str, Any]:
        return {
            "name": self.name_,
            "description": self.description_,
            "params": self.get_params(),
            "parameter_names": list(self.parameter_names_),
            "forms": list(self.forms_),
            "n_components": self.n_components_,
            "domain": self.domain_.to_dict(),
            "training_set": self.training_set_,
            "holdout_scores": self.holdout_scores_,
            "training_rms": self.training_rms_,
            "reconstruction_rms": self.reconstruction_rms_,
            "units": {"wavelengths_nm": "nm", "reflectance": "1 (fraction)"},
        }

    def _arrays(self) -> dict[str, np.ndarray]:
        arrays = {
            "wavelengths_nm": self.wavelengths_,
            "mean": self.mean_,
            "components": self.components_,
            "explained_variance_ratio": self.explained_variance_ratio_,
            "scale_center": self.scale_center_,
            "scale_halfwidth": self.scale_halfwidth_,
        }
        if self.regressor == "network":
            parameters, shapes = self.network_.to_arrays()
            arrays.update(
                network_parameters=parameters,
                network_shapes=shapes,
                network_output_scale=np.array([self.network_output_scale_]),
            )
            if self.physical_inputs:
                arrays.update(physical_center=self.physical_center_, physical_halfwidth=self.physical_halfwidth_)
        else:
            arrays.update(powers=self.powers_, W=self.W_)
        return arrays

    @classmethod
    def _from_parts(cls, meta: Mapping, data: Mapping[str, np.ndarray], path: Path) -> SpectralModel:
        model = cls._params_from_file(meta["params"])
        domain = Domain.from_dict(meta["domain"])
        regression = _NETWORK_ARRAYS if model.regressor == "network" else _MONOMIAL_ARRAYS
        if model.physical_inputs:
            if model.regressor != "network":
                raise ValueError("physical_inputs need regressor 'network'")
            regression += _PHYSICAL_ARRAYS
        wrong = sorted((set(_MONOMIAL_ARRAYS + _NETWORK_ARRAYS + _PHYSICAL_ARRAYS) - set(regression)) & set(data))
        missing = [a for a in regression if a not in data]
        if wrong or missing:
            raise ValueError(
                f"a {model.regressor} model needs the arrays {list(regression)}: {missing} missing, {wrong} foreign"
            )
        n_wl, d, k = data["wavelengths_nm"].shape[0], len(domain.names), int(meta["n_components"])
        n_forms = len(meta["forms"])
        expected = {
            "wavelengths_nm": (n_wl,),
            "mean": (n_wl,),
            "components": (k, n_wl),
            "scale_center": (d,),
            "scale_halfwidth": (d,),
        }
        integers = ("powers", "network_shapes")
        if model.regressor == "network":
            network = Network.from_arrays(data["network_parameters"], data["network_shapes"])
            n_physical = len(model.physical_inputs)
            n_inputs = d + (n_forms if n_forms > 1 else 0) + n_physical
            if (network.n_inputs, network.n_outputs) != (n_inputs, k):
                raise ValueError(
                    f"the network maps {network.n_inputs} inputs to {network.n_outputs} outputs, "
                    f"expected {n_inputs} to {k}"
                )
            expected["network_output_scale"] = (1,)
            expected.update(dict.fromkeys(_PHYSICAL_ARRAYS, (n_physical,)) if n_physical else {})
        else:
            n_inputs = d + (n_forms - 1 if model.forms == "onehot" and n_forms > 1 else 0)
            n_groups = n_forms if model.forms == "separate" else 1
            m = data["powers"].shape[0]
            expected.update(powers=(m, n_inputs), W=(n_groups, m, k))
        for name, shape in expected.items():
            if data[name].shape != shape:
                raise ValueError(f"array {name!r} has shape {data[name].shape}, expected {shape}")
        for name in (*_ARRAYS, *regression):
            if data[name].dtype.kind not in ("i" if name in integers else "f"):
                raise ValueError(f"array {name!r} has dtype {data[name].dtype}")
            if not np.isfinite(data[name]).all():
                raise ValueError(f"array {name!r} holds NaN or inf")
        if list(meta["parameter_names"]) != list(domain.names):
            raise ValueError("parameter_names differ from the domain's dimensions")
        center, halfwidth = data["scale_center"], data["scale_halfwidth"]
        c, h = domain.scaling()
        if not (np.allclose(center, c, rtol=1e-12) and np.allclose(halfwidth, h, rtol=1e-12)):
            raise ValueError("the feature scaling does not match the domain")
        model.wavelengths_ = data["wavelengths_nm"]
        model.domain_ = domain
        model.parameter_names_ = domain.names
        model.forms_ = tuple(meta["forms"])
        model.n_features_in_ = d
        model.n_components_ = k
        model.mean_, model.components_ = data["mean"], data["components"]
        model.explained_variance_ratio_ = data["explained_variance_ratio"]
        model.scale_center_, model.scale_halfwidth_ = center, halfwidth
        if model.regressor == "network":
            model.network_ = network
            model.network_output_scale_ = float(data["network_output_scale"][0])
            if model.physical_inputs:
                if not (data["physical_halfwidth"] > 0).all():
                    raise ValueError("array 'physical_halfwidth' holds a value <= 0")
                model.physical_center_ = data["physical_center"]
                model.physical_halfwidth_ = data["physical_halfwidth"]
        else:
            model.powers_, model.W_ = data["powers"].astype(np.int64), data["W"]
            model._plan = monomial_plan(model.powers_)
        model.training_set_ = meta.get("training_set") or {}
        model.holdout_scores_ = meta.get("holdout_scores")
        model.training_rms_ = meta.get("training_rms")
        model.reconstruction_rms_ = meta.get("reconstruction_rms")
        model.name_ = str(meta.get("name") or path.stem)  # format 1 had no name
        model.description_ = str(meta.get("description", ""))
        return model


@dataclass(frozen=True)
class _TrainingData:
    """The checked arguments of :meth:`SpectralModel.fit`."""

    values: np.ndarray  # (n, d) raw parameter values
    codes: np.ndarray  # (n,) form codes into domain.forms
    R: np.ndarray  # (n, n_wl) reflectance
    stderr: np.ndarray | None  # (n, n_wl) its Monte Carlo standard errors
    wavelengths: np.ndarray  # (n_wl,) nm
    domain: Domain
    info: dict  # the training-set reference from a dataset's attributes


def _least_squares(Phi: np.ndarray, T: np.ndarray, ridge: float) -> np.ndarray:
    """argmin_W ‖Φ W − T‖² + λ ‖W[1:]‖² (the constant's coefficient, row 0, is not penalised).

    Solved as ordinary least squares on Φ stacked over √λ·I (no normal equations: they square
    the condition number of Φ).
    """
    if ridge > 0:
        m = Phi.shape[1]
        penalty = math.sqrt(ridge) * np.eye(m)[1:]
        Phi = np.vstack([Phi, penalty])
        T = np.vstack([T, np.zeros((m - 1, T.shape[1]))])
    W, *_ = np.linalg.lstsq(Phi, T, rcond=None)
    return W


# ---- hold-out evaluation ----------------------------------------------------------------------
@dataclass(frozen=True)
class HoldoutReport:
    """Errors of a model against Monte Carlo hold-out samples (reflectance fractions).

    Attributes
    ----------
    wavelengths_nm : ndarray (n_wl,)
    rms_error, max_error, mean_error : ndarray (n_wl,)
        RMS, maximum absolute and mean (bias) of prediction − Monte Carlo, per wavelength.
    mc_noise_rms : ndarray (n_wl,)
        RMS of the Monte Carlo standard errors of the hold-out samples: the part of
        ``rms_error`` that is noise in the reference, not error of the model.
    n_samples : int
    """

    wavelengths_nm: np.ndarray
    rms_error: np.ndarray
    max_error: np.ndarray
    mean_error: np.ndarray
    mc_noise_rms: np.ndarray
    n_samples: int

    @property
    def rms_error_overall(self) -> float:
        return float(np.sqrt(np.mean(self.rms_error**2)))

    @property
    def max_error_overall(self) -> float:
        return float(self.max_error.max())

    @property
    def model_error_estimate(self) -> np.ndarray:
        """RMS error against noise-free reflectance, per wavelength: √max(rms² − noise², 0)
        (prediction and reference noise are independent, so their variances add)."""
        return np.sqrt(np.maximum(self.rms_error**2 - self.mc_noise_rms**2, 0.0))

    def to_dict(self) -> dict:
        return {
            "n_samples": self.n_samples,
            "wavelengths_nm": self.wavelengths_nm.tolist(),
            "rms_error": self.rms_error.tolist(),
            "max_error": self.max_error.tolist(),
            "mean_error": self.mean_error.tolist(),
            "mc_noise_rms": self.mc_noise_rms.tolist(),
            "rms_error_overall": self.rms_error_overall,
            "max_error_overall": self.max_error_overall,
        }

    def table(self) -> str:
        """Plain-text table, one row per wavelength."""
        lines = [
            f"hold-out: {self.n_samples} samples; RMS error {self.rms_error_overall:.5f}, "
            f"max error {self.max_error_overall:.5f}",
            f"{'wavelength nm':>13} {'RMS error':>10} {'max error':>10} {'bias':>10} "
            f"{'MC noise':>10} {'model err.':>10}",
        ]
        for row in zip(
            self.wavelengths_nm,
            self.rms_error,
            self.max_error,
            self.mean_error,
            self.mc_noise_rms,
            self.model_error_estimate,
        ):
            lines.append(f"{row[0]:13.1f} " + " ".join(f"{v:10.5f}" for v in row[1:]))
        return "\n".join(lines)


def evaluate(model: SpectralModel, holdout: str | Path | xr.Dataset, *, attach: bool = False) -> HoldoutReport:
    """Compare a model with Monte Carlo reflectance of samples not used in fitting.

    Parameters
    ----------
    model : SpectralModel
    holdout : str, Path or xarray.Dataset
        A training-set dataset (:func:`generate_training_set`) of hold-out samples, at the
        model's wavelengths.
    attach : bool
        Also store the scores in ``model.holdout_scores_`` (saved with the model).

    Returns
    -------
    HoldoutReport
    """
    import xarray as xr

    if isinstance(holdout, (str, Path)):
        with xr.open_dataset(holdout) as ds:
            holdout = ds.load()
    wl = holdout["wavelength"].values
    if wl.shape != model.wavelengths_.shape or not np.allclose(wl, model.wavelengths_):
        raise ParameterError(
            "holdout wavelengths", wl.tolist(), f"the model's wavelengths {model.wavelengths_.tolist()}"
        )
    reference = holdout["reflectance"].values
    error = model.predict(holdout) - reference
    report = HoldoutReport(
        wavelengths_nm=wl,
        rms_error=np.sqrt(np.mean(error**2, axis=0)),
        max_error=np.abs(error).max(axis=0),
        mean_error=error.mean(axis=0),
        mc_noise_rms=np.sqrt(np.mean(holdout["stderr"].values ** 2, axis=0)),
        n_samples=int(reference.shape[0]),
    )
    if attach:
        model.holdout_scores_ = report.to_dict()
    return report
