"""sandlight: predictive simulation of the appearance of sand.

From what a geologist measures of a sand sample (iron oxides and where they sit, water, grain
sizes and shapes) to spectral reflectance, BRDF, colour and rendered landscapes.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("sandlight")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"

from sandlight.errors import SandlightError, ParameterError, ModelFileError  # noqa: E402

__all__ = ["SandlightError", "ParameterError", "ModelFileError", "__version__"]
