"""Where an appearance's parts come from: the sample, r(λ) and the spatial model.

Public objects
--------------
resolve_sample
    A `SandSample` from a sample, a preset name or a dict of parameters.
resolve_spectral
    Wavelengths and r(λ) from a spectral model, a model file or a callable.
resolve_spatial
    A `SpatialModel` from a model, a model file or None (the shipped one).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.predictor.spectral import SpectralModel
    from sandlight.sample import SandSample
    from sandlight.spatial.model import SpatialModel

__all__ = ["resolve_sample", "resolve_spectral", "resolve_spatial"]


def resolve_sample(sample: SandSample | str | dict) -> SandSample:
    """The sample itself, the preset of that name, or `SandSample.from_dict` of the parameters.

    Raises
    ------
    ParameterError
        ``sample`` is none of these.
    """
    from sandlight.sample import SandSample

    if isinstance(sample, SandSample):
        return sample
    if isinstance(sample, str):
        return SandSample.preset(sample)
    if isinstance(sample, dict):
        return SandSample.from_dict(sample)
    raise ParameterError("sample", type(sample).__name__, "a SandSample, a preset name or a dict of parameters")


def resolve_spectral(
    model: SpectralModel | str | Path | Callable | None, sample: SandSample
) -> tuple[np.ndarray, np.ndarray, str, str | None]:
    """r(λ) of ``sample`` from the spectral ``model``.

    Parameters
    ----------
    model : SpectralModel, path, callable or None
        None: the shipped model (`sandlight.predictor.default_model`); a path: a model file; a
        callable ``sample -> (wavelengths_nm, reflectance)``.
    sample : SandSample

    Returns
    -------
    wavelengths_nm : numpy.ndarray (W,)
        Increasing, nm.
    reflectance : numpy.ndarray (W,)
        r(λ), dimensionless, unclipped.
    source : str
        A description of the model.
    memory : str or None
        The engine path memory the model was trained with (None: unknown, e.g. for a callable).

    Raises
    ------
    ParameterError
        ``model`` is none of these, or returns malformed wavelengths or reflectances.
    """
    from sandlight.predictor.spectral import SpectralModel

    if model is None:
        from sandlight.predictor import default_model

        model = default_model()
    if isinstance(model, (str, Path)):
        model = SpectralModel.load(model)
    if hasattr(model, "predict") and hasattr(model, "wavelengths_"):
        wl, r = np.asarray(model.wavelengths_, dtype=float), np.asarray(model.predict([sample]), dtype=float)[0]
        source = f"{type(model).__name__} ({len(wl)} wavelengths)"
    elif callable(model):
        wl, r = (np.asarray(x, dtype=float) for x in model(sample))
        source = getattr(model, "__qualname__", repr(model))
    else:
        raise ParameterError(
            "spectral_model",
            type(model).__name__,
            "None (the shipped model), a SpectralModel, a model file, or a callable "
            "sample -> (wavelengths_nm, reflectance)",
        )
    if (
        wl.ndim != 1
        or wl.shape != r.shape
        or wl.size < 1
        or not (np.isfinite(wl).all() and np.isfinite(r).all())
        or np.any(np.diff(wl) <= 0)
    ):
        raise ParameterError(
            "spectral_model",
            f"wavelengths of shape {wl.shape}, reflectance of shape {r.shape}",
            "increasing finite wavelengths (nm) and one finite reflectance per wavelength",
        )
    return wl, r, source, getattr(model, "memory_", None)


def resolve_spatial(model: SpatialModel | str | Path | None, sample: Any = None) -> SpatialModel:
    """The spatial ``model`` itself, loaded from a file, or (None) the shipped model that covers
    ``sample`` (one sample or a sequence sharing one model; `sandlight.spatial.model_for`), the
    default beach model when no sample is given.

    Raises
    ------
    ParameterError
        ``model`` is none of these.
    """
    from sandlight.spatial.model import SpatialModel, default_model
    from sandlight.spatial.shipped import model_for

    if model is None:
        return default_model() if sample is None else model_for(sample)
    if isinstance(model, (str, Path)):
        return SpatialModel.load(model)
    if isinstance(model, SpatialModel):
        return model
    raise ParameterError(
        "spatial_model", type(model).__name__, "None (the shipped model), a SpatialModel or a model file"
    )
