"""Would a coherent (thin-film) coating change what a coated grain absorbs? (docs/model.md §2.4,
item 2, "Coherence").

The engine treats an iron-oxide coating as an incoherent slab between two Fresnel interfaces
(``layers.rs``). The coatings of the presets are 10–100 nm thick, below the coherence length of
daylight (≈ 0.6 µm), so a smooth film of that thickness would interfere. This study compares, for
one plane stack air | coating | quartz, the incoherent recursion the engine uses with the Airy
formula of a single absorbing film (Born & Wolf, *Principles of Optics*, 7th ed., §1.6.4 and
§14.4.1; s and p separately, then averaged) at the coating thickness and composition
:func:`sandlight.physics.composition.compose` gives each sample, and at 10 nm and 0.001 nm of the
same coating. Light meets the stack from the pore (air) and from inside the grain (quartz), with
the cosine-weighted angular distribution of a diffuse field (the grain's interior includes the
totally internally reflected part). Printed: absorptance A and reflectance R of each treatment,
400–700 nm.

Usage::

    python scripts/studies/coherent_coating.py
"""

from __future__ import annotations

import numpy as np

from sandlight.optics import complex_index
from sandlight.physics.composition import HOST_MATERIAL, compose
from sandlight.sample import SandSample

WAVELENGTHS_NM = (400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0)
#: Cosine nodes of the angular average (midpoints of 2000 equal cells in μ).
MU = (np.arange(2000) + 0.5) / 2000


def _cosines(n_from: complex, n: complex, mu: np.ndarray) -> np.ndarray:
    """cos θ in medium ``n`` for incidence cosine ``mu`` in ``n_from`` (principal branch)."""
    s = n_from * np.sqrt(1.0 - mu**2)
    return np.sqrt(1.0 - (s / n) ** 2 + 0j)


def coherent(n0: float, film: complex, n2: float, thickness_nm: float, wavelength_nm: float, mu: np.ndarray):
    """(R, T) of the film between n0 and n2, incidence cosine ``mu`` in n0, unpolarised (Airy)."""
    c0, c1, c2 = mu + 0j, _cosines(n0, film, mu), _cosines(n0, n2, mu)
    beta = 2.0 * np.pi / wavelength_nm * film * thickness_nm * c1
    phase = np.exp(2j * beta)
    r_sum, t_sum = 0.0, 0.0
    # Fresnel amplitudes with the admittances η = n cos θ (s) and n / cos θ (p) (Born & Wolf §1.5).
    for eta in (lambda n, c: n * c, lambda n, c: n / c):
        e0, e1, e2 = eta(n0, c0), eta(film, c1), eta(n2, c2)
        r01, r12 = (e0 - e1) / (e0 + e1), (e1 - e2) / (e1 + e2)
        t01, t12 = 2 * e0 / (e0 + e1), 2 * e1 / (e1 + e2)
        r = (r01 + r12 * phase) / (1 + r01 * r12 * phase)
        t = t01 * t12 * np.exp(1j * beta) / (1 + r01 * r12 * phase)
        r_sum = r_sum + np.abs(r) ** 2
        # Power transmittance: the ratio of the admittances' real parts (zero beyond the critical angle).
        t_sum = t_sum + np.abs(t) ** 2 * np.real(e2) / np.real(e0)
    return r_sum / 2, t_sum / 2


def _fresnel(n_a: float, n_b: float, mu: np.ndarray):
    """Unpolarised reflectance a | b and the cosine in b (0 and R = 1 beyond the critical angle)."""
    cb2 = 1.0 - (n_a / n_b) ** 2 * (1.0 - mu**2)
    cb = np.sqrt(np.clip(cb2, 0.0, None))
    rs = ((n_a * mu - n_b * cb) / (n_a * mu + n_b * cb)) ** 2
    rp = ((n_b * mu - n_a * cb) / (n_b * mu + n_a * cb)) ** 2
    return np.where(cb2 > 0, (rs + rp) / 2, 1.0), cb


def incoherent(n0: float, film: complex, n2: float, thickness_nm: float, wavelength_nm: float, mu: np.ndarray):
    """(R, T) of the engine's incoherent slab (layers.rs: real indices at the interfaces, τ inside)."""
    ra, c1 = _fresnel(n0, film.real, mu)
    rb, _ = _fresnel(film.real, n2, np.where(c1 > 0, c1, 1.0))
    alpha = 4.0 * np.pi * film.imag / wavelength_nm
    tau = np.where(c1 > 0, np.exp(-alpha * thickness_nm / np.where(c1 > 0, c1, 1.0)), 0.0)
    den = 1.0 - ra * rb * tau**2
    r = ra + (1 - ra) ** 2 * tau**2 * rb / den
    t = (1 - ra) * tau * (1 - rb) / den
    return np.where(c1 > 0, r, 1.0), np.where(c1 > 0, t, 0.0)


def diffuse(rt, *args) -> tuple[float, float]:
    """Absorptance and reflectance for cosine-weighted incidence (2μ dμ)."""
    r, t = rt(*args, MU)
    w = 2.0 * MU
    r_mean, t_mean = float(np.mean(r * w)), float(np.mean(t * w))
    return 1.0 - r_mean - t_mean, r_mean


def table(name: str, coating: dict, thickness_nm: float) -> None:
    print(f"\n{name}: coating {thickness_nm:.3g} nm, " + ", ".join(f"{m} {v:.3f}" for m, v in coating.items()))
    print(
        "| λ (nm) | coating n + ik | from air: A incoherent / coherent | R incoherent / coherent |"
        " from quartz: A incoherent / coherent | R incoherent / coherent |"
    )
    print("|---|---|---|---|---|---|")
    for lam in WAVELENGTHS_NM:
        film = sum(v * complex(complex_index(m, lam)) for m, v in coating.items())
        n_host = complex(complex_index(HOST_MATERIAL, lam)).real
        cells = [f"{film.real:.2f} + {film.imag:.3f}i"]
        for n0, n2 in ((1.0, n_host), (n_host, 1.0)):
            (ai, ri), (ac, rc) = (diffuse(f, n0, film, n2, thickness_nm, lam) for f in (incoherent, coherent))
            cells += [f"{ai:.3f} / {ac:.3f}", f"{ri:.3f} / {rc:.3f}"]
        print(f"| {lam:.0f} | " + " | ".join(cells) + " |")


def main() -> None:
    for preset in ("red-dune", "yellow-dune"):
        sand = compose(SandSample.preset(preset)).populations[0]
        thickness_nm = sand.coating_thickness_mm * 1e6
        for t in (thickness_nm, 10.0, 0.001):
            table(preset if t == thickness_nm else f"{preset}, thinner", sand.coating, t)


if __name__ == "__main__":
    main()
