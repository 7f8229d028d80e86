"""Optics of a pigmented coating: iron-oxide crystals in a kaolinite matrix, from Lorenz–Mie.

The uniform coating of docs/model.md §2.4 absorbs with the volume mean of its materials' bulk
α = 4πk/λ, as if the pigment were molecularly dispersed, and does not scatter. Real coatings on
red and yellow sand grains are clay films holding iron-oxide crystals of ~0.05–0.2 µm
(Schwertmann & Cornell, *Iron Oxides in the Laboratory*, 2nd ed., 2000, ch. 1 and 10; Torrent &
Barrón, "Diffuse reflectance spectroscopy of iron oxides", *Encyclopedia of Surface and Colloid
Science*, 2002): particles comparable to the wavelength, which scatter as much as they absorb.
This module gives the coating's coefficients from the Mie cross sections of those crystals
(docs/model.md §2.4, "Pigmented coating (Mie)"):

* number density of crystals of diameter d at volume share v in the coating: N = v / (π d³/6);
  each has cross sections C = Q π d²/4, so per unit volume (independent scattering,
  Bohren & Huffman 1983 §3.4): α_p = Σ v·(3/2)·Q_abs/d, σ = Σ v·(3/2)·Q_sca/d;
* asymmetry of the mixture: g = Σ v Q_sca g / Σ v Q_sca (cross-section-weighted mean);
* Mie in the matrix: relative index m = (n + ik)_pigment / n_kaolinite, size parameter
  x = π d n_kaolinite / λ (Bohren & Huffman's convention, :mod:`sandlight.physics.mie`);
* the matrix absorbs with its own bulk α = 4πk/λ over its volume share (1 − Σ v);
* the coating's real index for the Fresnel reflection at its faces is the matrix's, n_kaolinite:
  the pigment's contrast acts through its scattering, which a mean index would count twice.

Departures (docs/model.md): independent scattering at pigment volume shares of tens of per cent
(dependent scattering lowers σ in dense packings; not modelled), spheres for platy hematite and
acicular goethite, one crystal size rather than a distribution.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from sandlight.errors import ParameterError
from sandlight.optics import complex_index
from sandlight.physics.mie import mie_efficiencies, size_parameter

__all__ = ["PIGMENT_DIAMETER_UM", "PIGMENTS", "MATRIX", "CoatingOptics", "coating_optics"]

#: Default diameter (µm) of the iron-oxide crystals in a coating: the logarithmic middle of the
#: 0.05–0.2 µm of pigmentary hematite and goethite in soils and red beds (Schwertmann & Cornell
#: 2000; Torrent & Barrón 2002). A physical default, not fitted to any spectrum.
PIGMENT_DIAMETER_UM = 0.1

#: The materials treated as Mie scatterers in a coating, and the matrix holding them.
PIGMENTS = ("hematite", "goethite")
MATRIX = "kaolinite"


@dataclass(frozen=True)
class CoatingOptics:
    """A pigmented coating at one wavelength: real index, absorption and scattering
    coefficients (mm⁻¹) and the asymmetry g of its scattering."""

    n: float
    absorption_per_mm: float
    scattering_per_mm: float
    asymmetry: float


def coating_optics(
    coating: Mapping[str, float],
    wavelength_nm: float,
    diameter_um: float = PIGMENT_DIAMETER_UM,
    *,
    optical_constants: Callable[[str, float], complex] = complex_index,
) -> CoatingOptics:
    """The optics of a coating of volume fractions ``coating`` (keys among :data:`PIGMENTS` and
    :data:`MATRIX`, summing to 1) at vacuum wavelength ``wavelength_nm`` (nm), its pigment
    spheres of diameter ``diameter_um`` (µm) in the matrix.

    ``optical_constants`` is ``(material, wavelength_nm) -> n + ik`` (the shipped tables by
    default).
    """
    unknown = sorted(set(coating) - set(PIGMENTS) - {MATRIX})
    if unknown:
        raise ParameterError(
            "coating", ", ".join(unknown), f"a pigmented coating holds {' and '.join(PIGMENTS)} in {MATRIX}"
        )
    if not (np.isfinite(diameter_um) and 0.005 <= diameter_um <= 20.0):
        raise ParameterError("pigment_diameter_um", diameter_um, "a diameter in [0.005, 20] µm")
    matrix = complex(optical_constants(MATRIX, wavelength_nm))
    d_mm = diameter_um * 1e-3
    alpha = sca = sca_g = 0.0
    for name in PIGMENTS:
        v = float(coating.get(name, 0.0))
        if v <= 0:
            continue
        m = complex(optical_constants(name, wavelength_nm)) / matrix.real
        q = mie_efficiencies(m, size_parameter(diameter_um, wavelength_nm, matrix.real))
        # N C = [v / (π d³/6)] · Q π d²/4 = (3/2) v Q / d.
        alpha += 1.5 * v * float(q.q_abs) / d_mm
        s = 1.5 * v * float(q.q_sca) / d_mm
        sca += s
        sca_g += s * float(q.g)
    v_pigment = sum(float(coating.get(p, 0.0)) for p in PIGMENTS)
    alpha += (1.0 - v_pigment) * 4.0 * np.pi * matrix.imag / (wavelength_nm * 1e-6)
    return CoatingOptics(matrix.real, alpha, sca, sca_g / sca if sca > 0 else 0.0)
