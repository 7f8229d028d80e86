"""The optical medium of a sample at one wavelength, as the native engine traces it.

Mixing rules (docs/transport.md): a core or coating made of several materials gets the
volume-weighted mean of their complex indices, n̄ = Σ vⱼ nⱼ and k̄ = Σ vⱼ kⱼ, hence the
volume-weighted absorption coefficient ᾱ = Σ vⱼ αⱼ — the dilute-inclusion limit of
splits-model.md §2.4 (Maxwell Garnett is the refinement for dense inclusions).
"""

from __future__ import annotations

import numpy as np

from sandlight import _native
from sandlight.optics import complex_index
from sandlight.physics.composition import Composition


def absorption_per_mm(k: float, wavelength_nm: float) -> float:
    """α = 4πk/λ in mm⁻¹ (λ in nm)."""
    return 4.0 * np.pi * k / (wavelength_nm * 1e-6)


def _mix(materials: dict, wavelength_nm: float) -> complex:
    return sum(v * complex(complex_index(m, wavelength_nm)) for m, v in materials.items())


def native_medium(comp: Composition, wavelength_nm: float, memory: str = "none") -> _native.Medium:
    """The native medium of composition ``comp`` at ``wavelength_nm`` (nm, vacuum).

    ``memory`` is the on-the-fly engine's near-surface path memory, 'none' (the classic model),
    'channel', 'cut' or 'packed' (docs/geometry.md).
    """
    probs = comp.encounter_probabilities()
    quantiles, aspect, core_n, core_k, core_a, coat_n, coat_a, coat_t = ([] for _ in range(8))
    for p in comp.populations:
        core = _mix(p.core, wavelength_nm)
        quantiles.append(p.sizes.encounter_quantiles().tolist())
        aspect.append(p.aspect_ratio)
        core_n.append(core.real)
        core_k.append(core.imag)
        core_a.append(absorption_per_mm(core.imag, wavelength_nm))
        if p.coating and p.coating_thickness_mm > 0:
            c = _mix(p.coating, wavelength_nm)
            coat_n.append(c.real)
            coat_a.append(absorption_per_mm(c.imag, wavelength_nm))
            coat_t.append(p.coating_thickness_mm)
        else:
            coat_n.append(1.0)
            coat_a.append(0.0)
            coat_t.append(0.0)
    water = complex(complex_index("water", wavelength_nm))
    return _native.Medium.particulate(
        probs,
        quantiles,
        aspect,
        core_n,
        core_k,
        core_a,
        coat_n,
        coat_a,
        coat_t,
        comp.mean_free_path_mm,
        water.real,
        absorption_per_mm(water.imag, wavelength_nm),
        comp.film_thickness_mm,
        comp.water_filled_probability,
        comp.depth_mm,
        memory=memory,
    )
