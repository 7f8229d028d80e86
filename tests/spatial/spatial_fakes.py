"""Synthetic goniophotometer and spectral predictor for the spatial and appearance tests
(module-level: job workers import it).

A node's "true" BRDF is azimuth-independent and reciprocal:

    f = 0.6 · Chandrasekhar(ω) + 0.2 · ω/π + 0.2 · G(μ_i) G(μ_o) / c,   G(μ) = exp(−μ/0.15),

with the single-scattering albedo ω(x) = 0.95 − 0.5·saturation − 2·iron_oxide, so that the shape
changes along the mesh, and a glancing term whose albedo (≤ exp(−μ_i/0.15) ≤ 1) makes the
directional-hemispherical reflectance rise steeply towards grazing incidence, as measured sand
does. Counts are multinomial draws (`sandlight.testing.synthetic_brdf.sample_counts`).
"""

import functools
import math

import numpy as np

from sandlight.gonio import CollectorHemisphere
from sandlight.testing import chandrasekhar, synthetic_brdf

#: Hemisphere and trials of the shared synthetic measurements (multinomial draws per row: cheap).
STACKS, SLICES = 7, 8
RAYS = 10**8
GLANCING_SCALE = 0.15
# c = ∫ G(μ) μ dω = 2π ∫_0^1 exp(−μ/s) μ dμ, so that the glancing term's albedo is G(μ_i) ≤ 1.
_C = 2 * math.pi * GLANCING_SCALE**2 * (1 - math.exp(-1 / GLANCING_SCALE) * (1 + 1 / GLANCING_SCALE))


def omega(params) -> float:
    return float(0.95 - 0.5 * params["saturation"] - 2.0 * params["iron_oxide"])


def true_brdf_mu(mu_out, mu_in, w):
    glancing = np.exp(-(mu_out + mu_in) / GLANCING_SCALE) / _C
    return 0.6 * chandrasekhar.brdf(mu_out, mu_in, w) + 0.2 * w / math.pi + 0.2 * glancing


@functools.lru_cache(maxsize=64)
def _probabilities(stacks, slices, w):
    h = CollectorHemisphere(stacks, slices)
    return synthetic_brdf.band_probabilities(h, lambda mo, mi: true_brdf_mu(mo, mi, w), order=6)


def probabilities(params, stacks, slices):
    return _probabilities(stacks, slices, round(omega(params), 12))


def fake_measure(params, wavelength_nm, *, rays, seed, stacks, slices, threads, checkpoint=None):
    h = CollectorHemisphere(stacks, slices)
    return synthetic_brdf.sample_counts(h, probabilities(params, stacks, slices), rays, seed=seed)


def fake_spectrum(sample):
    """A spectral 'model' as a callable: bright, rising reflectance (0.55–0.9) darkened by water."""
    wl = np.arange(400.0, 701.0, 20.0)
    s = sample.to_dict()
    r = (0.55 + 0.35 * (wl - 400.0) / 300.0) * (1.0 - 0.4 * s["saturation"])
    return wl, r


def measured_nodes(mesh, rays, *, stacks=7, slices=8, seed=0, method="average"):
    """MeasuredBRDF of every node of ``mesh`` from the synthetic goniophotometer (no job)."""
    from sandlight.gonio import MeasuredBRDF

    out = []
    for i, params in enumerate(mesh.sample_dict(x) for x in mesh.nodes):
        counts = fake_measure(params, 550.0, rays=rays, seed=seed + i, stacks=stacks, slices=slices, threads=1)
        out.append(
            MeasuredBRDF.from_counts(
                **counts, stacks=stacks, slices=slices, sample=params, wavelength_nm=550.0, seed=seed + i, method=method
            )
        )
    return out


def expected_unique(params, stacks=7, slices=8):
    """The noise-free normalised unique values the synthetic measurement converges to."""
    from sandlight.gonio import CollectorHemisphere, EquivalenceClasses

    h = CollectorHemisphere(stacks, slices)
    f = synthetic_brdf.expected_brdf(h, probabilities(params, stacks, slices))
    classes = EquivalenceClasses(h)
    unique = classes.mean(f)
    cap = classes.class_of[h.cap]
    reflectance = float(np.dot(h.projected_solid_angles, unique[cap]))
    return unique / reflectance


def fake_reflectance(params, wavelengths_nm):
    """Synthetic training reflectance for a small SpectralModel: bright quartz (up to 0.85),
    darkened by iron oxide in the blue and by water."""
    wl = (np.asarray(wavelengths_nm, dtype=float) - 400.0) / 300.0
    iron = np.sqrt(params["iron_oxide"] / 0.10)
    return (0.45 + 0.4 * wl) * (1 - 0.6 * iron * (1 - wl)) * (1 - 0.45 * params["saturation"])


def fitted_spectral_model(n=400, seed=1):
    """A degree-1 SpectralModel over the default domain, fitted to `fake_reflectance`."""
    from sandlight.predictor import Domain, SpectralModel

    domain = Domain.default()
    samples = domain.draw(n, seed, "random")
    wl = np.arange(400.0, 701.0, 20.0)
    R = np.array([fake_reflectance(s, wl) for s in samples])
    return SpectralModel(degree=1).fit(samples, R, wavelengths_nm=wl, domain=domain)
