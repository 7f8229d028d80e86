"""Synthetic goniophotometer for the spatial tests (module-level: job workers import it).

A node's "true" BRDF is Chandrasekhar's half-space of isotropic scatterers with single-scattering
albedo ω(x) depending smoothly on the mesh parameters (saturation darkens, iron oxide darkens), so
that BRDFs vary in shape along the mesh, plus a Lambertian share; counts are multinomial draws
(`sandlight.gonio.synthetic.sample_counts`) on a small hemisphere.
"""

import functools

import numpy as np

from sandlight.gonio import CollectorHemisphere
from sandlight.gonio import synthetic


def omega(params) -> float:
    return float(0.95 - 0.5 * params["saturation"] - 2.0 * params["iron_oxide"])


@functools.lru_cache(maxsize=64)
def _probabilities(stacks, slices, w):
    h = CollectorHemisphere(stacks, slices)
    return 0.7 * synthetic.chandrasekhar_probabilities(h, w, order=6) + 0.3 * synthetic.lambertian_probabilities(h, w)


def probabilities(params, stacks, slices):
    return _probabilities(stacks, slices, round(omega(params), 12))


def fake_measure(params, wavelength_nm, *, rays, seed, stacks, slices, threads, checkpoint=None):
    h = CollectorHemisphere(stacks, slices)
    return synthetic.sample_counts(h, probabilities(params, stacks, slices), rays, seed=seed)
