"""The fit of log10 k(λ) to end-member spectra: penalised least squares on tabulated ρ(λ, k).

Public objects
--------------
KFit
    Estimator: ``fit(tables, measured)`` finds log10 k at every wavelength of the tables;
    ``predict(tables)`` gives the reflectance of (other) end-members at that k.
holdout
    Fit on some end-members, predict the others: the cross-validation of issue 17 §1 (b).

The problem (docs/optical-constants.md, "Calibration on pure end-members"). With x_i = log10 k
at wavelength λ_i, minimise

    Σ_s Σ_i [(ρ_s(λ_i, x_i) − m_si) / σ_si]²  +  Σ_i r_i²  +  Σ_i [(x_i − p_i) / σ_p]²,
    r_i = √(smoothing · w_i / h) · h² · x''(λ_i),

where m_si is the measurement of end-member s, σ_si² = σ_meas² + σ_MC,si² + σ_model²
(measurement and Monte Carlo standard errors, the latter at the current k, and an optional
model error), x''(λ_i) the three-point second
derivative on the (possibly non-uniform) grid, w_i = (λ_{i+1} − λ_{i−1})/2 the grid weight and
h = ``reference_step_nm``; the last sum is an optional weak prior, p_i = log10 of a literature k
(``prior_log10_k``, :mod:`sandlight.calibration.priors`) with σ_p = ``prior_sigma_log10_k``
decades. On a uniform grid of step h, r_i = √smoothing · (x_{i−1} − 2x_i +
x_{i+1}): the penalty is the discrete ∫ x''² dλ, the same for any grid density. The fit is
:func:`scipy.optimize.least_squares` (trust region reflective, bounds = the tables' k range)
with the exact, sparse Jacobian, started from the per-wavelength best value on a fine grid (with
the prior's term, if any); σ_MC
(and σ_model) are then updated at the solution and the fit repeated, three passes in all.

The model error. When the model cannot reproduce the spectra (χ²/dof ≫ 1 with the measurement
and Monte Carlo errors alone), those errors are not the errors of the fit: the data terms then
outweigh the penalty far more than intended, and every σ derived from them is too small.
``model_sigma="auto"`` estimates one σ_model for all points, the value that makes χ² equal to
its degrees of freedom (Σ r²/(σ² + σ_model²) = dof; 0 when χ²/dof ≤ 1 already). Where no
end-member constrains k
(opaque or transparent everywhere), the penalty alone sets it: x is interpolated smoothly
across — or, with a prior, drawn to the literature value — and the identifiability report
(:mod:`sandlight.calibration.report`) says so.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy import sparse
from scipy.optimize import brentq, least_squares

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.calibration.tables import ReflectanceTable

__all__ = ["KFit", "holdout"]

#: Points of the grid used to start the fit (per-wavelength best value).
_START_POINTS = 241
#: Largest reflectance accepted as a fraction (a percent scale would be far above).
_MAX_REFLECTANCE = 1.5


def _second_derivative_operator(wl: np.ndarray, smoothing: float, h: float) -> sparse.csr_matrix:
    """Matrix D with (D x)_i = r_i, the penalty residuals of the module docstring (rows i = 1..n−2)."""
    n = wl.size
    if n < 3 or smoothing == 0.0:
        return sparse.csr_matrix((0, n))
    hm, hp = np.diff(wl)[:-1], np.diff(wl)[1:]
    # x''_i = 2 [ (x_{i+1} − x_i)/h₊ − (x_i − x_{i−1})/h₋ ] / (h₋ + h₊)
    a = 2.0 / (hm * (hm + hp))
    c = 2.0 / (hp * (hm + hp))
    b = -(a + c)
    scale = np.sqrt(smoothing * 0.5 * (hm + hp) / h) * h**2
    rows = np.repeat(np.arange(n - 2), 3)
    cols = (np.arange(n - 2)[:, None] + np.arange(3)).ravel()
    vals = (np.stack([a, b, c], axis=1) * scale[:, None]).ravel()
    return sparse.csr_matrix((vals, (rows, cols)), shape=(n - 2, n))


def _model_sigma(residuals: np.ndarray, sigma: np.ndarray, dof: int) -> float:
    """σ_m ≥ 0 with Σ r²/(σ² + σ_m²) = dof (0 if the χ² is at most dof already)."""

    def excess(sm: float) -> float:
        return float(np.sum(residuals**2 / (sigma**2 + sm**2))) - max(dof, 1)

    if excess(0.0) <= 0.0:
        return 0.0
    return float(brentq(excess, 0.0, float(np.max(np.abs(residuals))) + 1.0))


class KFit:
    """Penalised least-squares fit of log10 k(λ) to measured end-member spectra.

    Parameters
    ----------
    smoothing : float
        Weight of the curvature penalty (≥ 0; see the module docstring). 0 fits every
        wavelength on its own.
    reference_step_nm : float
        Grid step h (nm, > 0) at which ``smoothing`` weighs a second difference of log10 k like
        a residual of one standard error.
    measurement_sigma : float
        Standard error of a measured reflectance where ``fit`` is given none (> 0).
    model_sigma : float or "auto"
        Model error added in quadrature to every point's standard error (≥ 0), or ``"auto"``
        to estimate it from the residuals (module docstring).
    max_nfev : int
        Maximum function evaluations of each least-squares pass (≥ 1).
    prior_log10_k : array_like or None
        log10 of a prior k at every wavelength of the tables (finite; see the module docstring),
        or None (default) for no prior.
    prior_sigma_log10_k : float
        Standard deviation σ_p of the prior in decades (> 0; default 1: a weak prior that
        decides k only where no end-member constrains it).

    Attributes (after ``fit``)
    --------------------------
    wavelengths_nm_ : numpy.ndarray, shape (nλ,)
    log10_k_ : numpy.ndarray, shape (nλ,)
        Fitted log10 k.
    k_ : numpy.ndarray, shape (nλ,)
    k_range_log10_ : (float, float)
        The bounds of log10 k: the range all tables cover.
    sigma_log10_k_ : numpy.ndarray, shape (nλ,)
        Standard error of log10 k from the Gauss–Newton covariance (JᵀJ)⁻¹ of the whole
        objective, i.e. with the smoothness penalty acting as a prior: where no measurement
        constrains k it says how far the interpolation can move, not what the data say (for
        that see :func:`sandlight.calibration.report.identifiability`).
    member_ids_ : tuple of str
    fitted_ : numpy.ndarray, shape (S, nλ)
        Model reflectance of the fitted end-members at ``log10_k_``.
    residuals_ : numpy.ndarray, shape (S, nλ)
        fitted_ − measured (NaN where not measured).
    sigma_ : numpy.ndarray, shape (S, nλ)
        The standard errors used in the last pass (measurement ⊕ Monte Carlo ⊕ model).
    model_sigma_ : float
        The model error used (the estimate for ``"auto"``).
    rms_ : dict[str, float]
        RMS of ``residuals_`` per end-member over its measured wavelengths.
    chi2_ : float
        Σ (residual/σ)² of the data terms with σ = measurement ⊕ Monte Carlo only (without the
        model error); ``dof_`` their number minus nλ.
    penalty_ : float
        The penalty term at the solution.
    result_ : scipy.optimize.OptimizeResult
        Of the last pass.
    """

    def __init__(
        self,
        smoothing: float = 10.0,
        reference_step_nm: float = 10.0,
        measurement_sigma: float = 0.005,
        model_sigma: float | str = 0.0,
        max_nfev: int = 1000,
        prior_log10_k: ArrayLike | None = None,
        prior_sigma_log10_k: float = 1.0,
    ):
        self.smoothing = smoothing
        self.reference_step_nm = reference_step_nm
        self.measurement_sigma = measurement_sigma
        self.model_sigma = model_sigma
        self.max_nfev = max_nfev
        self.prior_log10_k = prior_log10_k
        self.prior_sigma_log10_k = prior_sigma_log10_k

    # --- validation -----------------------------------------------------------------------

    def _check_parameters(self) -> None:
        def positive(name: str, value: object, zero_ok: bool = False) -> None:
            ok = isinstance(value, (int, float, np.floating)) and not isinstance(value, bool) and math.isfinite(value)
            if not ok or value < 0 or (value == 0 and not zero_ok):
                raise ParameterError(name, value, "a finite number " + (">= 0" if zero_ok else "> 0"))

        positive("smoothing", self.smoothing, zero_ok=True)
        positive("reference_step_nm", self.reference_step_nm)
        positive("measurement_sigma", self.measurement_sigma)
        if not (isinstance(self.model_sigma, str) and self.model_sigma == "auto"):
            if isinstance(self.model_sigma, str):
                raise ParameterError("model_sigma", self.model_sigma, 'a finite number >= 0 or "auto"')
            positive("model_sigma", self.model_sigma, zero_ok=True)
        if isinstance(self.max_nfev, bool) or not isinstance(self.max_nfev, (int, np.integer)) or self.max_nfev < 1:
            raise ParameterError("max_nfev", self.max_nfev, "an integer >= 1")
        positive("prior_sigma_log10_k", self.prior_sigma_log10_k)

    def _prior(self, n: int) -> tuple[np.ndarray, sparse.csr_matrix]:
        """(p/σ_p, I/σ_p): the prior's residuals are I/σ_p · x − p/σ_p (empty without a prior)."""
        if self.prior_log10_k is None:
            return np.zeros(0), sparse.csr_matrix((0, n))
        allowed = f"None or {n} finite values of log10 k, one per wavelength of the tables"
        try:
            p = np.asarray(self.prior_log10_k, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError("prior_log10_k", self.prior_log10_k, allowed) from None
        if p.shape != (n,) or not np.all(np.isfinite(p)):
            raise ParameterError("prior_log10_k", f"array of shape {p.shape}", allowed)
        s = float(self.prior_sigma_log10_k)
        return p / s, sparse.identity(n, format="csr") / s

    @staticmethod
    def _check_tables(
        tables: Sequence[ReflectanceTable], wavelengths: np.ndarray | None = None
    ) -> list[ReflectanceTable]:
        tables = list(tables) if isinstance(tables, Sequence) else None
        if not tables:
            raise ParameterError("tables", tables, "a non-empty sequence of ReflectanceTable")
        reference = tables[0].wavelengths_nm if wavelengths is None else wavelengths
        for t in tables:
            if not np.array_equal(t.wavelengths_nm, reference):
                raise ParameterError(
                    "tables",
                    t.member_id,
                    "tables on one wavelength grid" + ("" if wavelengths is None else ", the grid of the fit"),
                )
        return tables

    def _check_measured(
        self, measured: ArrayLike, sigma: ArrayLike | None, shape: tuple[int, int]
    ) -> tuple[np.ndarray, np.ndarray]:
        try:
            m = np.asarray(measured, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError("measured", measured, "reflectances as numbers") from None
        allowed = (
            f"an array of shape {shape} (end-members × wavelengths) of reflectance fractions in "
            f"[0, {_MAX_REFLECTANCE:g}], NaN where not measured, at least one value"
        )
        if m.shape != shape:
            raise ParameterError("measured", f"array of shape {m.shape}", allowed)
        finite = np.isfinite(m)
        if np.isinf(m).any() or np.any((m[finite] < 0) | (m[finite] > _MAX_REFLECTANCE)) or not finite.any():
            bad = m[~np.isnan(m) & ((m < 0) | (m > _MAX_REFLECTANCE) | np.isinf(m))]
            raise ParameterError("measured", f"array containing {bad.flat[0] if bad.size else 'no value'!r}", allowed)
        if sigma is None:
            s = np.where(finite, float(self.measurement_sigma), np.nan)
        else:
            try:
                s = np.broadcast_to(np.asarray(sigma, dtype=float), shape).copy()
            except (TypeError, ValueError):
                raise ParameterError("sigma", sigma, f"positive standard errors broadcastable to {shape}") from None
            if not np.all(np.isfinite(s[finite]) & (s[finite] > 0)):
                raise ParameterError("sigma", sigma, "finite and > 0 wherever measured is a number")
        return m, s

    # --- fit ------------------------------------------------------------------------------

    def fit(self, tables: Sequence[ReflectanceTable], measured: ArrayLike, sigma: ArrayLike | None = None) -> KFit:
        """Fits log10 k at each wavelength of the tables.

        Parameters
        ----------
        tables : sequence of ReflectanceTable
            One per end-member, all on one wavelength grid.
        measured : array_like, shape (S, nλ)
            Measured reflectance (fraction) of each end-member at the tables' wavelengths; NaN
            where there is no measurement.
        sigma : array_like or None
            Measurement standard errors, broadcastable to (S, nλ); None: ``measurement_sigma``.

        Returns
        -------
        KFit
            self, with the attributes of the class docstring.
        """
        self._check_parameters()
        tables = self._check_tables(tables)
        wl = tables[0].wavelengths_nm
        m, s_meas = self._check_measured(measured, sigma, (len(tables), wl.size))
        low = max(t.log10_k[0] for t in tables)
        high = min(t.log10_k[-1] for t in tables)
        if not low < high:
            raise ParameterError("tables", [t.member_id for t in tables], "log10 k grids that overlap")
        mask = np.isfinite(m)
        penalty = _second_derivative_operator(wl, float(self.smoothing), float(self.reference_step_nm))
        prior_offset, prior = self._prior(wl.size)

        def sigma_at(x: np.ndarray) -> np.ndarray:
            mc = np.array([t.stderr_at(x) for t in tables])
            return np.sqrt(s_meas**2 + mc**2)

        def model(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            both = [t(x) for t in tables]
            return np.array([b[0] for b in both]), np.array([b[1] for b in both])

        x = self._start(tables, m, s_meas, mask, low, high, prior_offset, prior)
        rows = np.nonzero(mask)  # (end-member, wavelength) of each data residual
        dof = int(mask.sum() - wl.size)
        model_sigma = 0.0 if self.model_sigma == "auto" else float(self.model_sigma)
        for _ in range(3):
            s = np.sqrt(sigma_at(x) ** 2 + model_sigma**2)

            def residuals(x: np.ndarray, s: np.ndarray = s) -> np.ndarray:
                rho, _ = model(x)
                return np.concatenate([((rho - m) / s)[mask], penalty @ x, prior @ x - prior_offset])

            def jacobian(x: np.ndarray, s: np.ndarray = s) -> sparse.csr_matrix:
                _, drho = model(x)
                data = (drho / s)[mask]
                data = sparse.csr_matrix((data, (np.arange(rows[0].size), rows[1])), shape=(rows[0].size, wl.size))
                return sparse.vstack([data, penalty, prior]).tocsr()

            result = least_squares(
                residuals,
                np.clip(x, low, high),
                jac=jacobian,
                bounds=(low, high),
                method="trf",
                x_scale=1.0,
                max_nfev=int(self.max_nfev),
            )
            x = result.x
            if self.model_sigma == "auto":
                model_sigma = _model_sigma((model(x)[0] - m)[mask], sigma_at(x)[mask], dof)
        rho, _ = model(x)
        jac = result.jac.toarray() if sparse.issparse(result.jac) else np.asarray(result.jac)
        covariance = np.linalg.pinv(jac.T @ jac)
        self.wavelengths_nm_ = wl.copy()
        self.k_range_log10_ = (float(low), float(high))
        self.log10_k_ = x
        self.k_ = 10.0**x
        self.sigma_log10_k_ = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
        self.member_ids_ = tuple(t.member_id for t in tables)
        self.fitted_ = rho
        self.residuals_ = np.where(mask, rho - m, np.nan)
        self.sigma_ = np.where(mask, s, np.nan)
        self.model_sigma_ = float(model_sigma)
        self.rms_ = {t.member_id: float(np.sqrt(np.nanmean(self.residuals_[i] ** 2))) for i, t in enumerate(tables)}
        self.chi2_ = float(np.sum((self.residuals_[mask] / sigma_at(x)[mask]) ** 2))
        self.dof_ = dof
        self.penalty_ = float(np.sum((penalty @ x) ** 2))
        self.result_ = result
        return self

    @staticmethod
    def _start(
        tables: Sequence[ReflectanceTable],
        m: np.ndarray,
        s: np.ndarray,
        mask: np.ndarray,
        low: float,
        high: float,
        prior_offset: np.ndarray,
        prior: sparse.csr_matrix,
    ) -> np.ndarray:
        """Per wavelength, the log10 k of a fine grid that minimises the weighted misfit (plus
        the prior's term, if there is one)."""
        grid = np.linspace(low, high, _START_POINTS)
        cost = np.zeros((grid.size, m.shape[1]))
        if prior_offset.size:
            cost += (grid[:, None] * prior.diagonal()[None, :] - prior_offset[None, :]) ** 2
        for i, t in enumerate(tables):
            d = (t.on_grid(grid) - m[i]) / s[i]
            cost += np.where(mask[i], d, 0.0) ** 2
        return grid[np.argmin(cost, axis=0)]

    # --- predict --------------------------------------------------------------------------

    def predict(self, tables: Sequence[ReflectanceTable]) -> np.ndarray:
        """Model reflectance of end-members at the fitted k.

        Parameters
        ----------
        tables : sequence of ReflectanceTable
            On the wavelength grid of the fit.

        Returns
        -------
        numpy.ndarray, shape (len(tables), nλ)
        """
        if not hasattr(self, "log10_k_"):
            raise ParameterError("KFit", "not fitted", "call fit(tables, measured) before predict")
        tables = self._check_tables(tables, self.wavelengths_nm_)
        return np.array([t(self.log10_k_)[0] for t in tables])


def holdout(
    estimator: KFit,
    tables: Sequence[ReflectanceTable],
    measured: ArrayLike,
    *,
    test_ids: Iterable[str],
    band_nm: tuple[float, float] = (350.0, 2500.0),
) -> tuple[KFit, dict[str, float]]:
    """Fits a copy of ``estimator`` on the end-members not in ``test_ids``, predicts those.

    Parameters
    ----------
    estimator : KFit
        Its parameters are used; it is not modified.
    tables : sequence of ReflectanceTable
    measured : array_like, shape (len(tables), nλ)
    test_ids : iterable of str
        Member ids held out (each must be among the tables', and at least one table must remain).
    band_nm : (float, float)
        Wavelength band (nm, inclusive) of the reported RMS.

    Returns
    -------
    fitted : KFit
        The copy, fitted on the others.
    rms : dict[str, float]
        RMS of (prediction − measured) per held-out id over ``band_nm``.
    """
    tables = list(tables)
    ids = [t.member_id for t in tables]
    test = list(test_ids)
    if not test or any(i not in ids for i in test) or len(set(test)) == len(ids):
        raise ParameterError("test_ids", test, "a non-empty subset of " + ", ".join(ids) + " that leaves one to fit")
    m = np.asarray(measured, dtype=float)
    train = [j for j, i in enumerate(ids) if i not in test]
    held = [ids.index(i) for i in test]
    fitted = copy.deepcopy(estimator).fit([tables[j] for j in train], m[train])
    predicted = fitted.predict([tables[j] for j in held])
    wl = fitted.wavelengths_nm_
    band = (wl >= band_nm[0]) & (wl <= band_nm[1])
    rms = {i: float(np.sqrt(np.nanmean((predicted[n] - m[held[n]])[band] ** 2))) for n, i in enumerate(test)}
    return fitted, rms
