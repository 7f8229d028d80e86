"""A fast, deterministic stand-in for the engine's powder (the calibration's forward model).

ρ(λ, k; d) = ρ_opaque + (1 − ρ_opaque) exp(−2 √(α d)), α = 4πk/λ, d the geometric mean of the
end-member's size limits: dark where a grain absorbs what enters it, bright where it does not,
the dependence on k d/λ that geometric optics gives (the form of Hapke's equivalent-slab
reflectance). "Monte Carlo" noise: the binomial standard error √(ρ(1 − ρ)/rays) times one
Gaussian draw per wavelength, seeded by ``seed``, the member's id and the wavelength: the same
for every k (common random numbers), independent between end-members (as in EnginePowder) and
between wavelengths.
"""

import zlib

import numpy as np

RHO_OPAQUE = 0.06


def true_reflectance(member, wavelengths_nm, k):
    wl_um = np.asarray(wavelengths_nm, dtype=float) * 1e-3
    d_um = float(np.sqrt(member.size_um[0] * member.size_um[1]))
    alpha = 4.0 * np.pi * k / wl_um
    return RHO_OPAQUE + (1.0 - RHO_OPAQUE) * np.exp(-2.0 * np.sqrt(alpha * d_um))


class FakePowder:
    """Forward-model interface of sandlight.calibration.forward; counts its calls."""

    def __init__(self, rays=4000, seed=0):
        self.rays = rays
        self.seed = seed
        self.calls = 0

    def settings(self, member, wavelengths_nm):
        return {"model": "fake", "rays": self.rays, "seed": self.seed}

    def reflectance(self, member, wavelengths_nm, k):
        self.calls += 1
        truth = true_reflectance(member, wavelengths_nm, k)
        stderr = np.sqrt(truth * (1 - truth) / self.rays)
        key = [self.seed, zlib.crc32(member.id.encode())]
        z = np.array([np.random.default_rng(key + [int(w * 1000)]).standard_normal() for w in wavelengths_nm])
        return truth + stderr * z, stderr
