"""Where the colour functions get a sample's spectral reflectance from.

Every function that needs a sample's reflectance takes an injectable *reflectance provider*:
any callable ``provider(samples, wavelengths_nm) -> array (n_samples, n_wavelengths)`` giving the
directional-hemispherical reflectance (a fraction) of each sample at the requested wavelengths.
Pass one as ``reflectance=`` to use the Monte Carlo engine, a measured library or a test double;
leave it ``None`` to use :func:`default_reflectance_provider`, the shipped spectral predictor.

Public objects
--------------
- :data:`ReflectanceProvider`: the callable type.
- :func:`default_reflectance_provider`: resolves the shipped spectral predictor.
- :func:`engine_reflectance_provider`: runs the Monte Carlo engine on each sample instead.
- :func:`reflectance_of`: calls a provider (or the default) and checks what it returns.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from sandlight.errors import SandlightError

__all__ = ["ReflectanceProvider", "default_reflectance_provider", "engine_reflectance_provider", "reflectance_of"]

ReflectanceProvider = Callable[[Sequence[Any], NDArray[np.float64]], NDArray[np.float64]]

_HOW_TO_INJECT = (
    "Pass reflectance=provider, a callable (samples, wavelengths_nm) -> array of shape "
    "(n_samples, n_wavelengths), e.g. one that runs the Monte Carlo engine on each sample."
)


def default_reflectance_provider() -> ReflectanceProvider:
    """The provider used when ``reflectance=None``: the shipped spectral predictor.

    Returns
    -------
    callable
        ``provider(samples, wavelengths_nm)`` backed by ``sandlight.predictor.default_model()``.
        It answers only at the wavelengths the model was trained at (its ``wavelengths_``).

    Raises
    ------
    SandlightError
        No spectral model can be imported; the message says how to pass ``reflectance=``.
    """
    try:
        from sandlight.predictor import default_model
    except ImportError as exc:
        raise SandlightError(
            f"No spectral model is available (importing sandlight.predictor.default_model "
            f"failed: {exc}). {_HOW_TO_INJECT}"
        ) from exc
    model = default_model()

    def predictor_reflectance(samples: Sequence[Any], wavelengths_nm: NDArray) -> NDArray:
        model_wl = np.asarray(model.wavelengths_, dtype=float)
        requested = np.asarray(wavelengths_nm, dtype=float)
        if model_wl.shape != requested.shape or not np.allclose(model_wl, requested):
            raise SandlightError(
                f"The default spectral model predicts at wavelengths {model_wl.tolist()} nm, "
                f"not at the requested {requested.tolist()} nm. Request the model's wavelengths "
                f"or pass reflectance=."
            )
        return np.asarray(model.predict(list(samples)), dtype=float)

    return predictor_reflectance


def engine_reflectance_provider(rays: int, *, seed: int = 0, threads: int | None = None) -> ReflectanceProvider:
    """A provider that computes each sample's reflectance with the Monte Carlo engine.

    Slower than the predictor (about ``rays`` × 16 ray paths per sample), but valid for any
    sample the engine accepts and at any wavelengths in 350–2500 nm, and always consistent with
    the engine's current physics.

    Parameters
    ----------
    rays : int
        Rays per wavelength and sample, ≥ 1 (the standard error of a reflectance r is
        √(r(1 − r)/rays): 0.005 at 10⁴ rays for r = 0.5).
    seed : int, optional
        Engine seed; every sample uses the same seed (common random numbers, so neighbouring
        swatches differ by their physics more than by their noise).
    threads : int or None, optional
        Engine threads; ``None`` uses all cores.

    Returns
    -------
    callable
        ``provider(samples, wavelengths_nm) -> (n_samples, n_wavelengths)``; the samples must be
        ``SandSample`` objects.
    """
    from sandlight.engine import reflectance

    def engine_reflectance(samples: Sequence[Any], wavelengths_nm: NDArray) -> NDArray:
        return np.array(
            [reflectance(s, wavelengths_nm, rays=rays, seed=seed, threads=threads).values for s in samples], dtype=float
        ).reshape(len(samples), -1)

    return engine_reflectance


def reflectance_of(
    samples: Sequence[Any], wavelengths_nm: NDArray[np.float64], reflectance: ReflectanceProvider | None = None
) -> NDArray[np.float64]:
    """Reflectance of samples from a provider, checked for shape and finiteness.

    Parameters
    ----------
    samples
        Sand samples (``SandSample`` or anything the provider understands), length n.
    wavelengths_nm
        Wavelengths λ, nm, shape (m,).
    reflectance
        The provider; ``None`` resolves :func:`default_reflectance_provider`.

    Returns
    -------
    numpy.ndarray, shape (n, m)
        Reflectance as a fraction.

    Raises
    ------
    SandlightError
        The provider returned the wrong shape or non-finite values.
    """
    provider = default_reflectance_provider() if reflectance is None else reflectance
    wl = np.asarray(wavelengths_nm, dtype=float)
    values = np.asarray(provider(samples, wl), dtype=float)
    expected = (len(samples), wl.size)
    if values.shape != expected:
        raise SandlightError(
            f"The reflectance provider {provider!r} returned an array of shape {values.shape}; "
            f"expected (n_samples, n_wavelengths) = {expected}."
        )
    if not np.all(np.isfinite(values)):
        raise SandlightError(f"The reflectance provider {provider!r} returned NaN or inf values.")
    return values
