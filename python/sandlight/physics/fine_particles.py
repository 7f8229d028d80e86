"""Fine iron-oxide particles as Lorenz–Mie volume scatterers in the pore space (engine option
``particle_optics='mie'``; docs/model.md §2.4 item 8, docs/transport.md "Fine particles as
volume scatterers").

In the ``particles`` form the hematite and goethite particles (``iron_oxide_particle_size_um``,
0.1–3 µm: size parameter x = π d n_host/λ of 0.1–30) are wave-optics objects. With
``particle_optics='mie'`` the engine traces them as volume scatterers in the pore space instead
of as geometric-optics spheres:

* a particle of diameter d has the extinction cross-section C_ext = Q_ext π d²/4 and albedo
  ω = Q_sca/Q_ext, with Q from Lorenz–Mie (Bohren & Huffman 1983, ch. 4;
  :mod:`sandlight.physics.mie`) at the relative index m = ñ_particle/n_pore and x = π d n_pore/λ,
  n_pore = 1 for air or the real index of water in a water-filled pore (the water's absorption
  is applied along the path, as for every path in a filled pore);
* a ray meets the population at its geometric rate (projected area πd²/4, docs/model.md §2.1)
  times Q_ext, i.e. the rate of real collisions is n ⟨C_ext⟩: the geometric encounter law with
  πd²/4 replaced by C_ext. Sizes a ray meets follow the area-weighted law p_enc (§2.2), so the
  population's mean efficiency is Q̄ = E_enc[Q(d)], its albedo Q̄_sca/Q̄_ext, and its phase
  function the Q_sca-weighted mean of the sizes' phase functions (size-averaged, as the sizes
  are forgotten after each event);
* the engine meets the population at its geometric rate times a **majorant** Q_max, the same at
  every wavelength (:func:`majorant`), and turns a fraction 1 − Q̄_ext/Q_max of the meetings
  into null collisions (delta tracking; ``crates/sandlight-core/src/volume_scatterer.rs``). So
  the free paths and the type choice do not depend on the wavelength, and spectral path sharing
  stays exact.

Q_max is the largest Q̄_ext over :data:`MAJORANT_GRID_NM` (every nm of the optical tables'
350–2500 nm, in air and, if pores can be water-filled, in water) times :data:`MAJORANT_MARGIN`;
a wavelength whose Q̄_ext would still exceed it (sharper than the 1 nm grid) is refused with an
error rather than biased. It depends on the sample and the optical constants only, never on the
wavelengths of a run.

Public objects
--------------
PARTICLE_OPTICS, DEFAULT_PARTICLE_OPTICS
    The engine option's values ('geometric' the default, 'mie').
MieOptics
    A population's size-averaged Mie optics in one pore medium at one wavelength.
size_nodes_um, mie_optics, majorant, check_below_majorant
    The sizes averaged over, the optics, the majorant, the probability of a real collision.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from sandlight.errors import ParameterError
from sandlight.physics.composition import Population
from sandlight.physics.mie import mie_efficiencies, phase_function, phase_table, size_parameter

__all__ = [
    "PARTICLE_OPTICS",
    "DEFAULT_PARTICLE_OPTICS",
    "MAJORANT_GRID_NM",
    "MAJORANT_MARGIN",
    "SIZE_NODES",
    "MieOptics",
    "size_nodes_um",
    "mie_optics",
    "majorant",
    "check_below_majorant",
]

#: How the separate iron-oxide particles of the ``particles`` form are traced: 'geometric'
#: (spheres in geometric optics, the engine the predictor bank was trained on) or 'mie' (volume
#: scatterers with Lorenz–Mie optics, this module).
PARTICLE_OPTICS = ("geometric", "mie")
DEFAULT_PARTICLE_OPTICS = "geometric"

#: Wavelengths (nm) over which the majorant is taken: every nm of the optical tables.
MAJORANT_GRID_NM = np.arange(350.0, 2500.5, 1.0)
#: Factor on the largest Q̄_ext of the grid, for the wavelengths between its nodes.
MAJORANT_MARGIN = 1.1
#: Sizes a polydisperse population is averaged over: the midpoints of this many equal-probability
#: bins of the sizes a ray meets (a monodisperse one has its one size).
SIZE_NODES = 16


@dataclass(frozen=True)
class MieOptics:
    """A population's size-averaged Mie optics in one pore medium at one wavelength.

    ``q_ext``, ``q_sca``: mean efficiencies over the sizes a ray meets (dimensionless);
    ``mu``, ``phase``: the phase function's nodes (cosines, −1 to 1) and values (sr⁻¹, any
    normalisation; the engine normalises its piecewise-linear interpolant).
    """

    q_ext: float
    q_sca: float
    mu: np.ndarray
    phase: np.ndarray

    @property
    def albedo(self) -> float:
        """ω = Q̄_sca/Q̄_ext."""
        return self.q_sca / self.q_ext


def size_nodes_um(population: Population) -> np.ndarray:
    """Diameters (µm) a population's Mie optics are averaged over, with equal weights: its size,
    or :data:`SIZE_NODES` equal-probability levels of the sizes a ray meets (area-weighted)."""
    q = population.sizes.encounter_quantiles()
    if q.size == 1:
        return q * 1e3
    levels = (np.arange(SIZE_NODES) + 0.5) / SIZE_NODES
    return np.interp(levels, np.linspace(0.0, 1.0, q.size), q) * 1e3


def mie_optics(core: complex, pore_n: float, diameters_um: np.ndarray, wavelength_nm: float) -> MieOptics:
    """Size-averaged optics of spheres of complex index ``core`` (n + ik, k ≥ 0) and diameters
    ``diameters_um`` (µm, equal weights) in a pore of real index ``pore_n`` at vacuum wavelength
    ``wavelength_nm`` (nm).

    The phase function is Σ Q_sca,k p_k(μ)/Σ Q_sca,k at the nodes of the largest sphere's
    sampling table (the finest: nodes grow with the series terms, :func:`~sandlight.physics.mie.phase_table`).
    """
    m = complex(core) / pore_n
    x = np.atleast_1d(size_parameter(diameters_um, wavelength_nm, pore_n))
    e = mie_efficiencies(m, x)
    q_ext, q_sca = np.atleast_1d(e.q_ext), np.atleast_1d(e.q_sca)
    table = phase_table(m, float(x.max()))
    if x.size == 1:
        phase = table.pdf
    else:
        phase = sum(q * phase_function(m, float(xk), table.mu) for q, xk in zip(q_sca, x)) / q_sca.sum()
    return MieOptics(float(q_ext.mean()), float(q_sca.mean()), table.mu, np.asarray(phase))


def majorant(
    core: Callable[[float], complex],
    pore_indices: Sequence[Callable[[float], float]],
    diameters_um: np.ndarray,
) -> float:
    """Q_max of a population: :data:`MAJORANT_MARGIN` × the largest Q̄_ext over
    :data:`MAJORANT_GRID_NM` and the pore media ``pore_indices`` (each ``wavelength_nm ->`` real
    index: air, and water when pores can be water-filled); ``core`` is ``wavelength_nm ->`` the
    particles' complex index."""
    wl = MAJORANT_GRID_NM
    cores = np.array([complex(core(float(w))) for w in wl])
    best = 0.0
    for pore in pore_indices:
        n = np.array([float(pore(float(w))) for w in wl])
        x = size_parameter(diameters_um[None, :], wl[:, None], n[:, None])
        m = np.broadcast_to((cores / n)[:, None], x.shape)
        q = np.asarray(mie_efficiencies(m, x).q_ext).mean(axis=1)
        best = max(best, float(q.max()))
    return MAJORANT_MARGIN * best


def check_below_majorant(optics: MieOptics, q_max: float, wavelength_nm: float) -> float:
    """Q̄_ext/Q_max, the probability of a real collision; refused (naming ``wavelength_nm``) if
    above 1."""
    ratio = optics.q_ext / q_max
    if ratio > 1.0:
        raise ParameterError(
            "wavelength_nm",
            wavelength_nm,
            f"a wavelength where the Mie extinction efficiency {optics.q_ext:.4g} of the iron-oxide particles "
            f"stays below its majorant {q_max:.4g} (taken every nm over 350–2500 nm with a margin "
            f"{MAJORANT_MARGIN}); a resonance sharper than that grid",
        )
    return ratio
