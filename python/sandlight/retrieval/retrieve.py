"""``sandlight.fit``: sample parameters from a measured spectrum, with their uncertainty.

The steps (docs/retrieval.md): read and check the spectrum (:mod:`.spectrum`), build the
observation on the forward model's wavelengths or a sensor's bands (:mod:`.observation`), the
free parameters and their bounds (:mod:`.space`; a pure-mineral powder's in
:mod:`.powder_forward`), maximise the likelihood whose covariance holds
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
from scipy.stats import qmc

from sandlight.errors import ParameterError
from sandlight.retrieval.engine_check import EngineCheck, check_with_engine
from sandlight.retrieval.fitting import maximise_likelihood
from sandlight.retrieval.forward import EngineForward, bank_candidates
from sandlight.retrieval.identifiability import scan_identifiability
from sandlight.retrieval.likelihood import GaussianLikelihood
from sandlight.retrieval.mask import BandMask
from sandlight.retrieval.observation import Observation, observe
from sandlight.retrieval.posterior import LaplacePosterior, sample_posterior
from sandlight.retrieval.powder_forward import POWDER_WAVELENGTHS_NM, PowderForward, PowderSpace
from sandlight.retrieval.result import FitResult
from sandlight.retrieval.sensors import SpectralResponse
from sandlight.retrieval.space import ParameterSpace
from sandlight.retrieval.spectrum import as_spectrum

if TYPE_CHECKING:
    from sandlight.predictor import ModelBank
    from sandlight.sample import SandSample

__all__ = ["fit", "shipped_bank_for", "METHODS", "POSTERIORS", "FORWARDS"]

METHODS = ("bank", "engine")
#: Forward models: the sand model (SandSample, bank or engine) or a pure-mineral powder (engine).
FORWARDS = ("sand", "powder")
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
#: Step (share of each parameter's range) of the powder's Jacobian for the posterior: 0.03 of
#: the three decades of diameter is 0.09 decades (a fifth of a size): above the scale on which
#: the common-random-number spectrum is rough, below the curvature of the spectrum in log d.
POWDER_JACOBIAN_STEP = 0.03
#: Replicate engine runs (other seeds) at the optimum of a powder fit that estimate the Monte
#: Carlo covariance of its spectrum (EngineForward.replicate_covariance).
POWDER_REPLICATES = 16
#: Points per free parameter of the design a powder fit starts from (the best of them). The
#: common-random-number objective of a powder is rough in the diameter: bumps of Δ(−log L)
#: ≈ 0.5–1 every 0.05 decades at 2000 rays, where the least squares from the centre stalls
#: (docs/retrieval.md, "Powder forward model"); a design of 24 points over three decades is one
#: point per 0.13 decades, and the least squares goes on from its best.
POWDER_DESIGN_POINTS = 24


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
    forward: str = "sand",
    material: str | None = None,
    memory: str | None = None,
    method: str | None = None,
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
        Parameters to fit (``sandlight.retrieval.space.FREEABLE``; for a powder
        ``sandlight.retrieval.powder_forward.POWDER_FREEABLE``: diameter_um, porosity,
        aspect_ratio, scale).
    fixed : dict, optional
        Values of other parameters (override ``sample``).
    forward : {'sand', 'powder'}
        'sand': the sand model (a SandSample). 'powder': a dry powder of one pure ``material``
        (:class:`sandlight.physics.powder.Powder`) traced by the engine, the diameter fitted in
        log10 µm (:mod:`sandlight.retrieval.powder_forward`); ``method`` is then 'engine'.
    material : str
        The powder's material (``sandlight.optics.MATERIALS``), with ``forward='powder'`` only.
    memory : {'none', 'channel', 'cut', 'packed'}, optional
        The engine's path memory for the powder, with ``forward='powder'`` only (None: 'none',
        the classic model; docs/retrieval.md, "Powder forward model").
    method : {'bank', 'engine'}, default 'bank' ('engine' for a powder)
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
        Predictor bank. Default: the shipped full-range bank (350–2500 nm) when the
        measurement (after the mask; or the sensor's bands) reaches outside 400–700 nm and one
        of its models can answer the fit (today: dry sand), else the paper's 400–700 nm bank
        (:func:`shipped_bank_for`). ``FitResult.model`` names the model that answered.
    rays, seed, threads :
        Engine settings of ``method='engine'``.
    check_rays : int
        Rays per wavelength of the engine check after a bank fit (0: no check).
    wavelengths : array_like, optional
        Wavelengths (nm) of the engine forward model (default: the bank's; for a powder
        400–1000 nm every 25 nm).
    starts : int
        Starting points of the least squares (bank; the engine starts once; a powder fit starts
        from the best of `POWDER_DESIGN_POINTS` per free parameter).
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
        channels, an unknown method or forward model, or no bank model covering the fit; for a
        powder an unknown material or powder parameter, or a value outside its bounds.
    """
    if forward not in FORWARDS:
        raise ParameterError("forward", forward, f"one of {', '.join(FORWARDS)}")
    if method is None:
        method = "engine" if forward == "powder" else "bank"
    if method not in METHODS:
        raise ParameterError("method", method, f"one of {', '.join(METHODS)}")
    if posterior not in POSTERIORS:
        raise ParameterError("posterior", posterior, f"one of {', '.join(POSTERIORS)}")
    if forward == "powder":
        if method != "engine":
            raise ParameterError("method", method, "'engine' with forward='powder' (the predictor bank holds sand)")
        if sample is not None:
            raise ParameterError("sample", type(sample).__name__, "None with forward='powder' (set fixed instead)")
        return _fit_powder(
            PowderSpace.build(free, fixed, material, "none" if memory is None else memory),
            as_spectrum(measured, name=spectrum_name),
            mask=BandMask.parse(mask),
            sensor=sensor,
            noise=noise,
            posterior=posterior,
            rays=rays,
            wavelengths=wavelengths,
            seed=seed,
            threads=threads,
        )
    if material is not None:
        raise ParameterError("material", material, "None unless forward='powder' (a sand's minerals are parameters)")
    if memory is not None:
        raise ParameterError(
            "memory", memory, "None unless forward='powder' (a sand is traced with the default engine)"
        )
    space = ParameterSpace.build(free, fixed, sample)
    spectrum = as_spectrum(measured, name=spectrum_name)
    mask = BandMask.parse(mask)
    needed = space.size + 1 + int(noise is None)
    if bank is None and (method == "bank" or wavelengths is None):
        bank = shipped_bank_for(spectrum, space, mask=mask, sensor=sensor)

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
        for model in candidates:
            likelihood = GaussianLikelihood(obs, model.budget())
            optimum = maximise_likelihood(model, model.space, likelihood, starts=starts, seed=seed)
            tried[model.name] = optimum.nll
            if best is None or optimum.nll < best[2].nll:
                best = (model, likelihood, optimum)

    if method == "engine":
        engine_space = space
        x0 = best[2].x if best is not None else space.centre()
        model = EngineForward(engine_space, grid, rays=rays, seed=seed, threads=threads)
        model.predict(x0[None, :])  # the Monte Carlo standard errors enter the budget
        likelihood = GaussianLikelihood(obs, model.budget())
        optimum = maximise_likelihood(
            model,
            engine_space,
            likelihood,
            x0=x0,
            diff_step=ENGINE_DIFF_STEP,
            tolerance=ENGINE_TOLERANCE,
            sigma0=best[2].sigma if best is not None else None,
            jacobian_step=_engine_jacobian_step(best, engine_space),
        )
        tried[model.name] = optimum.nll
        best = (model, likelihood, optimum)

    model, likelihood, optimum = best
    check = None
    if method == "bank" and check_rays:
        engine = EngineForward(model.space, model.grid, rays=check_rays, seed=seed + 1, threads=threads)
        assumed = float(np.sqrt(np.mean((obs.operator @ model.model_rms) ** 2)))
        check = check_with_engine(engine, obs, optimum.x, optimum.model, assumed, rays=check_rays, seed=seed + 1)
    return _result(best, obs, method, posterior, seed, tried, check)


def shipped_bank_for(
    spectrum: Any,
    space: ParameterSpace,
    *,
    mask: BandMask | None = None,
    sensor: str | os.PathLike | SpectralResponse | None = None,
) -> ModelBank:
    """The shipped bank a sand fit asks when none is given: the full-range bank (350–2500 nm)
    when the measurement has channels outside the paper's 400–700 nm that it would observe and
    one of its models can answer the fit; the paper's bank otherwise.

    The paper's models are the more accurate inside 400–700 nm (docs/spectral-predictor.md),
    but a spectrum's near infrared holds what the visible cannot tell apart (grain size, the
    860 nm hematite band), so the bank that sees more of the measurement answers.
    """
    from sandlight.predictor import default_model, full_range_model

    paper, full = default_model(), full_range_model()
    if full is paper:
        return paper
    low, high = paper.wavelengths_[0], paper.wavelengths_[-1]
    try:
        candidates = bank_candidates(full, space)
        centres = observe(spectrum, candidates[0].grid, mask=mask, sensor=sensor).centres_nm
    except ParameterError:
        return paper  # no full-range model answers this fit, or it observes nothing
    return full if np.any((centres < low) | (centres > high)) else paper


def _fit_powder(
    space: PowderSpace,
    spectrum: Any,
    *,
    mask: BandMask | None,
    sensor: str | os.PathLike | SpectralResponse | None,
    noise: ArrayLike | None,
    posterior: str,
    rays: int,
    wavelengths: ArrayLike | None,
    seed: int,
    threads: int | None,
) -> FitResult:
    """`fit` with ``forward='powder'``: the engine over a PowderSpace, started from the best
    point of a design (`POWDER_DESIGN_POINTS`), refitted with the replicate covariance."""
    grid = np.asarray(POWDER_WAVELENGTHS_NM if wavelengths is None else wavelengths, dtype=float)
    obs = observe(
        spectrum,
        grid,
        mask=mask,
        sensor=sensor,
        noise=noise,
        min_channels=space.size + 1 + int(noise is None),
    )
    forward = PowderForward(space, grid, rays=rays, seed=seed, threads=threads)
    forward.predict(space.centre()[None, :])  # the Monte Carlo standard errors enter the budget
    settings = {
        "diff_step": ENGINE_DIFF_STEP,
        "tolerance": ENGINE_TOLERANCE,
        "jacobian_step": np.full(space.size, POWDER_JACOBIAN_STEP),
    }
    likelihood = GaussianLikelihood(obs, forward.budget())
    x0 = _best_of_design(forward, space, likelihood, POWDER_DESIGN_POINTS * space.size, seed)
    optimum = maximise_likelihood(forward, space, likelihood, x0=x0, **settings)
    # then the Monte Carlo covariance from replicates at the optimum, and the fit again from there
    forward.replicate_covariance(optimum.x, POWDER_REPLICATES)
    likelihood = GaussianLikelihood(obs, forward.budget())
    optimum = maximise_likelihood(forward, space, likelihood, x0=optimum.x, sigma0=optimum.sigma, **settings)
    return _result((forward, likelihood, optimum), obs, "engine", posterior, seed, {forward.name: optimum.nll}, None)


def _best_of_design(
    forward: PowderForward, space: PowderSpace, likelihood: GaussianLikelihood, points: int, seed: int
) -> np.ndarray:
    """The point of lowest −log L (σ at its best per point when unknown) among the centre and a
    Latin hypercube of ``points`` over the bounds: the start of the least squares."""
    u = np.vstack([np.full(space.size, 0.5), qmc.LatinHypercube(d=space.size, seed=seed).random(points)])
    x = space.from_unit(u)
    r = likelihood.obs.values - forward.predict(x) @ likelihood.obs.operator.T
    sigma = None if likelihood.known else np.array([likelihood.best_sigma(row) for row in r])
    return x[int(np.argmin(likelihood.nll(r, sigma)))]


def _result(
    best: tuple,
    obs: Observation,
    method: str,
    posterior: str,
    seed: int,
    tried: dict[str, float],
    check: EngineCheck | None,
) -> FitResult:
    """Posterior, identifiability scan and FitResult at the optimum of ``best``."""
    forward, likelihood, optimum = best
    fspace = forward.space
    dof = obs.size - fspace.size - 1 if optimum.sigma is not None else None
    post = LaplacePosterior.at(optimum.x, optimum.jacobian, fspace, dof)
    if posterior == "emcee":
        post = sample_posterior(forward, fspace, likelihood, post, optimum.sigma, seed=seed)
    flat = scan_identifiability(forward, fspace, likelihood, optimum.x, optimum.sigma, points=SCAN_POINTS[method])
    sigma = optimum.sigma if optimum.sigma is not None else float(np.sqrt(np.mean(obs.sigma**2)))
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
