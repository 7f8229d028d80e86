"""``sandlight.fit``: sample parameters from a measured spectrum, with their uncertainty.

The steps (docs/retrieval.md): read and check the spectrum (:mod:`.spectrum`), build the
observation on the forward model's wavelengths or a sensor's bands (:mod:`.observation`), the
free parameters and their bounds (:mod:`.space`), maximise the likelihood whose covariance holds
the measurement noise, the forward model's error and the Monte Carlo noise (:mod:`.likelihood`,
:mod:`.fitting`), approximate the posterior (:mod:`.posterior`), scan each parameter for a flat
likelihood (:mod:`.identifiability`) and, for a predictor fit, run the engine at the optimum
(:mod:`.engine_check`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.retrieval.engine_check import check_with_engine
from sandlight.retrieval.fitting import maximise_likelihood
from sandlight.retrieval.forward import EngineForward, bank_candidates
from sandlight.retrieval.identifiability import scan_identifiability
from sandlight.retrieval.likelihood import GaussianLikelihood
from sandlight.retrieval.mask import BandMask
from sandlight.retrieval.observation import observe
from sandlight.retrieval.posterior import LaplacePosterior, sample_posterior
from sandlight.retrieval.result import FitResult
from sandlight.retrieval.sensors import SpectralResponse
from sandlight.retrieval.space import ParameterSpace
from sandlight.retrieval.spectrum import as_spectrum

if TYPE_CHECKING:
    from sandlight.predictor import ModelBank
    from sandlight.sample import SandSample

__all__ = ["fit", "METHODS", "POSTERIORS"]

METHODS = ("bank", "engine")
POSTERIORS = ("laplace", "emcee")
#: Points of the identifiability scan along each parameter (predictor, engine).
SCAN_POINTS = {"bank": 21, "engine": 7}
#: Relative finite-difference step of the Jacobian with the engine (see fitting.maximise_likelihood).
ENGINE_DIFF_STEP = 0.02
#: Convergence tolerance of the engine fit (scipy's ftol/xtol/gtol, in coordinates scaled to the
#: bounds; the relative change of an estimated σ): 10⁻³ of a parameter's range is far below any
#: interval the engine's noise allows, and each evaluation is a Monte Carlo run.
ENGINE_TOLERANCE = 1e-3
#: Steps (shares of each parameter's range) of the engine's Jacobian for the posterior: one
#: posterior standard deviation of the bank's fit, within these limits. With one seed the
#: engine's spectrum is not smooth in every parameter: water changes the paths, so a change of
#: saturation by 0.02 moves the spectrum by Monte Carlo noise (about 0.01 at 5000 rays,
#: scripts/studies/retrieval_engine_roughness.py), and local slopes overstate the information.
#: The slope over ±1 standard deviation is the one the Laplace approximation needs, and averages
#: the roughness out.
ENGINE_JACOBIAN_STEP = (0.01, 0.1)


def _engine_jacobian_step(bank_fit: tuple | None, space: ParameterSpace) -> np.ndarray:
    """`ENGINE_JACOBIAN_STEP`: the bank fit's posterior standard deviations over the ranges."""
    lo, hi = ENGINE_JACOBIAN_STEP
    if bank_fit is None:
        return np.full(space.size, hi)
    forward, _, optimum = bank_fit
    sd = LaplacePosterior.at(optimum.x, optimum.jacobian, forward.space, None).sd
    return np.clip(sd / (space.high - space.low), lo, hi)


def fit(
    measured: Any,
    free: Any,
    fixed: Mapping[str, Any] | None = None,
    *,
    method: str = "bank",
    sample: SandSample | None = None,
    noise: ArrayLike | None = None,
    mask: BandMask | str | Sequence | None = None,
    sensor: str | os.PathLike | SpectralResponse | None = None,
    posterior: str = "laplace",
    bank: ModelBank | None = None,
    rays: int = 20_000,
    check_rays: int = 20_000,
    wavelengths: ArrayLike | None = None,
    seed: int = 0,
    threads: int | None = None,
    starts: int = 4,
    spectrum_name: str | None = None,
) -> FitResult:
    """Fit sample parameters to a measured reflectance spectrum.

    Parameters
    ----------
    measured : (wavelengths_nm, reflectance) pair, xarray.DataArray or path
        The spectrum (directional-hemispherical reflectance, fraction): arrays, a DataArray on a
        ``wavelength`` coordinate in nm, or a CSV, USGS splib07 ASCII or ENVI spectral-library
        file (:func:`sandlight.retrieval.spectrum.as_spectrum`).
    free : list of str or comma-separated str
        Parameters to fit (``sandlight.retrieval.space.FREEABLE``).
    fixed : dict, optional
        Values of other parameters (override ``sample``).
    method : {'bank', 'engine'}
        'bank': the shipped predictor bank (fast; the answering model's hold-out error enters
        the error budget; then an engine check at the optimum). 'engine': the Monte Carlo
        engine itself at ``rays`` rays, one seed for every evaluation (common random numbers),
        started from the bank's optimum when the bank covers the fit.
    sample : SandSample, optional
        Values of the parameters neither free nor in ``fixed`` (default ``SandSample()``).
    noise : float, array or None
        Measurement standard deviation (reflectance), one for all channels or one per channel;
        None estimates one σ from the residuals (intervals then use Student's t).
    mask : BandMask, 'water-vapour', '1350-1450,1800-1950' or list of (low, high) nm, optional
        Wavelengths left out.
    sensor : str, path or SpectralResponse, optional
        Fit in the bands of a sensor ('landsat-oli', 'sentinel2-msi' or an SRF CSV file).
    posterior : {'laplace', 'emcee'}
        Laplace approximation at the optimum, or MCMC samples (emcee).
    bank : ModelBank, optional
        Predictor bank (default the shipped one).
    rays, seed, threads :
        Engine settings of ``method='engine'``.
    check_rays : int
        Rays per wavelength of the engine check after a bank fit (0: no check).
    wavelengths : array_like, optional
        Wavelengths (nm) of the engine forward model (default: the bank's).
    starts : int
        Starting points of the least squares (bank; the engine starts once).
    spectrum_name : str, optional
        The spectrum to read from an ENVI library holding several.

    Returns
    -------
    FitResult

    Raises
    ------
    ParameterError
        Bad input, naming the parameter and what is allowed: unknown/non-freeable/duplicated
        free parameters or ones also fixed, NaN or µm wavelengths, a mask leaving too few
        channels, an unknown method, or no bank model covering the fit.
    """
    if method not in METHODS:
        raise ParameterError("method", method, f"one of {', '.join(METHODS)}")
    if posterior not in POSTERIORS:
        raise ParameterError("posterior", posterior, f"one of {', '.join(POSTERIORS)}")
    space = ParameterSpace.build(free, fixed, sample)
    spectrum = as_spectrum(measured, name=spectrum_name)
    mask = BandMask.parse(mask)
    needed = space.size + 1 + int(noise is None)
    if bank is None and (method == "bank" or wavelengths is None):
        from sandlight.predictor import default_model

        bank = default_model()

    candidates = []
    if method == "bank":
        candidates = bank_candidates(bank, space)
    elif bank is not None:
        try:
            candidates = bank_candidates(bank, space)
        except ParameterError:
            candidates = []
    grid = np.asarray(wavelengths if wavelengths is not None else bank.wavelengths_, dtype=float)
    obs = observe(
        spectrum,
        grid if method == "engine" else candidates[0].grid,
        mask=mask,
        sensor=sensor,
        noise=noise,
        min_channels=needed,
    )

    tried = {}
    best = None
    if candidates and (method == "bank" or wavelengths is None):
        for forward in candidates:
            likelihood = GaussianLikelihood(obs, forward.budget())
            optimum = maximise_likelihood(forward, forward.space, likelihood, starts=starts, seed=seed)
            tried[forward.name] = optimum.nll
            if best is None or optimum.nll < best[2].nll:
                best = (forward, likelihood, optimum)

    if method == "engine":
        engine_space = space
        x0 = best[2].x if best is not None else space.centre()
        forward = EngineForward(engine_space, grid, rays=rays, seed=seed, threads=threads)
        forward.predict(x0[None, :])  # the Monte Carlo standard errors enter the budget
        likelihood = GaussianLikelihood(obs, forward.budget())
        optimum = maximise_likelihood(
            forward,
            engine_space,
            likelihood,
            x0=x0,
            diff_step=ENGINE_DIFF_STEP,
            tolerance=ENGINE_TOLERANCE,
            sigma0=best[2].sigma if best is not None else None,
            jacobian_step=_engine_jacobian_step(best, engine_space),
        )
        tried[forward.name] = optimum.nll
        best = (forward, likelihood, optimum)

    forward, likelihood, optimum = best
    fspace = forward.space
    dof = obs.size - fspace.size - 1 if optimum.sigma is not None else None
    post = LaplacePosterior.at(optimum.x, optimum.jacobian, fspace, dof)
    if posterior == "emcee":
        post = sample_posterior(forward, fspace, likelihood, post, optimum.sigma, seed=seed)
    flat = scan_identifiability(forward, fspace, likelihood, optimum.x, optimum.sigma, points=SCAN_POINTS[method])
    sigma = optimum.sigma if optimum.sigma is not None else float(np.sqrt(np.mean(obs.sigma**2)))
    check = None
    if method == "bank" and check_rays:
        engine = EngineForward(fspace, forward.grid, rays=check_rays, seed=seed + 1, threads=threads)
        assumed = float(np.sqrt(np.mean((obs.operator @ forward.model_rms) ** 2)))
        check = check_with_engine(engine, obs, optimum.x, optimum.model, assumed, rays=check_rays, seed=seed + 1)
    chi2 = float(np.sum(likelihood.whiten(optimum.residual, optimum.sigma) ** 2))
    return FitResult(
        sample=fspace.sample(optimum.x),
        free=fspace.free,
        estimate=fspace.values(optimum.x),
        posterior=post,
        max_delta_chi2=flat,
        observation=obs,
        optimum=optimum,
        model=forward.describe(),
        method=method,
        sigma=sigma,
        sigma_estimated=optimum.sigma is not None,
        space=fspace,
        chi2=chi2,
        candidates=tried,
        engine_check=check,
    )
