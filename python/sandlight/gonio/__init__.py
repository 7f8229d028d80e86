"""The virtual goniophotometer: BRDF of a sand sample from Monte Carlo counts (paper §3.2.1–3.2.4).

Modules
-------
hemisphere
    `CollectorHemisphere`: equal-solid-angle patches (geometry from the Rust core).
symmetry
    `EquivalenceClasses`: patch pairs equal by isotropy and reciprocity; compress/expand.
reduction
    `reduce_counts`: estimate, symmetrise, normalise, with standard errors.
brdf
    `MeasuredBRDF`: counts, reduced values, metadata and the continuous BRDF f(ω_i, ω_o).
io
    `to_netcdf` / `read_netcdf`: the 'sandlight-brdf' NetCDF format.
plots
    Polar heat map and principal-plane curves.

Counts drawn from known BRDFs, to test the reduction, are in `sandlight.testing.synthetic_brdf`.

The transport engine fills the counters (``sandlight-core/src/gonio/tally.rs``); everything after
the counts happens here.
"""

from sandlight.gonio.brdf import MeasuredBRDF
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.gonio.io import read_netcdf, to_netcdf
from sandlight.gonio.reduction import ReducedBRDF, reduce_counts, reduce_fixed_incidence
from sandlight.gonio.symmetry import EquivalenceClasses

__all__ = [
    "CollectorHemisphere",
    "EquivalenceClasses",
    "MeasuredBRDF",
    "ReducedBRDF",
    "reduce_counts",
    "reduce_fixed_incidence",
    "to_netcdf",
    "read_netcdf",
]
