"""The explicit spectral BRDF of a sand sample (paper §3.3): evaluation, sampling, albedo, tables.

`SandAppearance` combines the spectral predictor (directional-hemispherical reflectance at normal
incidence r(λ), `sandlight.predictor`) with the spatial predictor (the BRDF normalised to unit
reflectance at normal incidence, f̂, `sandlight.spatial`) into f(ω_i, ω_o, λ), in sr⁻¹, for
directions in the local frame (z = the surface normal; ω_i towards the light, ω_o towards the
viewer; any positive length).

Modules
-------
band_grid
    `BandGrid`: f̂ on its nodes in μ (the cap as a step, mirror symmetry, non-negativity, exact
    normalisation) and the quadrature weights of the interpolant.
combination
    `Combination`: how r(λ) and f̂ combine ('energy', the default, or the paper's 'product'), the
    reference reflectance r_0 and the diffuse profile.
shapes
    `ShapeSeries`: one spatial shape at every wavelength ('fixed', the paper's) or the shape at
    the sand's reflectance at each wavelength ('reflectance', the default where the spatial model
    interpolates in log r₀).
sampling
    `SamplingTables`: the BRDF-following sampler (cells, tables, pdf) and cosine sampling.
sources
    Resolving the sample, the spectral model and the spatial model from what the user passes.
table_file
    The BRDF table file (format 'sandlight-brdf-table'): layout, atomic writer, checked reader.
sand_appearance
    `SandAppearance`: the user class, which builds the parts and delegates to them.
"""

from sandlight.appearance.combination import COMBINATIONS
from sandlight.appearance.sampling import DEFENSIVE_COSINE_SHARE, SAMPLING_METHODS
from sandlight.appearance.sand_appearance import SandAppearance
from sandlight.appearance.shapes import SHAPES
from sandlight.appearance.table_file import FORMAT_NAME as TABLE_FORMAT
from sandlight.appearance.table_file import FORMAT_VERSION as TABLE_FORMAT_VERSION

__all__ = [
    "SandAppearance",
    "TABLE_FORMAT",
    "TABLE_FORMAT_VERSION",
    "DEFENSIVE_COSINE_SHARE",
    "COMBINATIONS",
    "SHAPES",
    "SAMPLING_METHODS",
]
