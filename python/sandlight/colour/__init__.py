"""Colour of sand (paper §4.1): spectrum → CIE XYZ → sRGB / CIELAB, swatch grids, colourisation.

Modules, one concept each:

- :mod:`~sandlight.colour.spectrum`: reflectance spectra at any sampling → XYZ (D50, CIE 1964 10°).
- :mod:`~sandlight.colour.srgb`: XYZ → sRGB in the ``"managed"`` and ``"paper"`` modes; CIELAB.
- :mod:`~sandlight.colour.provider`: where a sample's reflectance comes from (injectable).
- :mod:`~sandlight.colour.sample_colour`: the colour of sand samples.
- :mod:`~sandlight.colour.swatches`: swatch grids, the paper's Figures 6 and 7.
- :mod:`~sandlight.colour.colourise`: colourisation of a photo of sand (§4.1.1).
- :mod:`~sandlight.colour.spectral_distribution`: spectra as ``colour.SpectralDistribution``.

See ``docs/colour.md``.
"""

from sandlight.colour.colourise import (
    ColourisedGrid,
    colourise,
    colourise_grid,
    default_texture_path,
    load_image,
    save_image,
)
from sandlight.colour.provider import (
    ReflectanceProvider,
    default_reflectance_provider,
    engine_reflectance_provider,
    reflectance_of,
)
from sandlight.colour.sample_colour import sample_lab, sample_rgb, sample_xyz
from sandlight.colour.spectral_distribution import from_spectral_distribution, to_spectral_distribution
from sandlight.colour.spectrum import (
    DEFAULT_ILLUMINANT,
    DEFAULT_OBSERVER,
    PREDICTOR_WAVELENGTHS_NM,
    spectrum_to_xyz,
    spectrum_to_xyz_under,
    white_point_xyz,
)
from sandlight.colour.srgb import (
    MODES,
    PAPER_XYZ_TO_LINEAR_RGB,
    paper_encoding,
    srgb_to_uint8,
    xyz_to_lab,
    xyz_to_srgb,
)
from sandlight.colour.swatches import (
    GridAxis,
    SwatchGrid,
    figure6,
    figure7,
    parse_grid_spec,
    swatch_grid,
)

__all__ = [
    "to_spectral_distribution",
    "from_spectral_distribution",
    "ColourisedGrid",
    "colourise",
    "colourise_grid",
    "default_texture_path",
    "load_image",
    "save_image",
    "ReflectanceProvider",
    "default_reflectance_provider",
    "engine_reflectance_provider",
    "reflectance_of",
    "sample_lab",
    "sample_rgb",
    "sample_xyz",
    "DEFAULT_ILLUMINANT",
    "DEFAULT_OBSERVER",
    "PREDICTOR_WAVELENGTHS_NM",
    "spectrum_to_xyz",
    "spectrum_to_xyz_under",
    "white_point_xyz",
    "MODES",
    "PAPER_XYZ_TO_LINEAR_RGB",
    "paper_encoding",
    "srgb_to_uint8",
    "xyz_to_lab",
    "xyz_to_srgb",
    "GridAxis",
    "SwatchGrid",
    "figure6",
    "figure7",
    "parse_grid_spec",
    "swatch_grid",
]
