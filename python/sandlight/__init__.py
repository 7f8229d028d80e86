"""sandlight: predictive simulation of the appearance of sand.

From what a geologist measures of a sand sample (iron oxides and where they sit, water, grain
sizes and shapes) to spectral reflectance, BRDF, colour and rendered landscapes.

>>> import sandlight
>>> sample = sandlight.SandSample.preset("red-dune")
>>> result = sandlight.reflectance(sample, [450, 550, 650], rays=2000, progress=False)
>>> result.values.shape
(3,)
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("sandlight")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"

from sandlight.errors import ModelFileError, ParameterError, SandlightError  # noqa: E402
from sandlight.sample import PARAMETERS, SandSample  # noqa: E402

_NATIVE_API = {
    "reflectance": "sandlight.engine",
    "isotropic_halfspace": "sandlight.engine",
    "ReflectanceResult": "sandlight.engine",
    "brdf": "sandlight.gonio.measure",
    "fixed_incidence": "sandlight.gonio.measure",
    "Traceable": "sandlight.physics.medium",
    "IsotropicScatterers": "sandlight.physics.media",
    "LambertianSurface": "sandlight.physics.media",
    "Powder": "sandlight.physics.powder",
    "SpectralModel": "sandlight.predictor",
    "predict": "sandlight.predictor.prediction",
    "SpatialModel": "sandlight.spatial",
    "SandAppearance": "sandlight.appearance",
    "fit": "sandlight.retrieval",
    "bands": "sandlight.retrieval",
    "FitResult": "sandlight.retrieval",
}


def __getattr__(name: str) -> object:
    # The engine needs the native extension; import it on first use so that pure-Python parts
    # (samples, colour, sky) work from a source tree without a build.
    if name in _NATIVE_API:
        import importlib

        return getattr(importlib.import_module(_NATIVE_API[name]), name)
    raise AttributeError(f"module 'sandlight' has no attribute {name!r}")


__all__ = [
    "SandlightError",
    "ParameterError",
    "ModelFileError",
    "SandSample",
    "PARAMETERS",
    "__version__",
    *_NATIVE_API,
]
