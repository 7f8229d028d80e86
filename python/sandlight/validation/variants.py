"""What-if runs: a validation sample's preset with one physical change at a time.

Variants are diagnostics, not fits: each tests whether one candidate cause (an absorption edge,
a particle size, a coating, the host's absorption) can move the model by the size of an
observed miss.

Public objects
--------------
Variant
    One change: sample parameters, or the optical constants of a material.
DIAGNOSTIC_VARIANTS
    The variants of the validation report.
run_variants
    Runs and scores variants like :func:`sandlight.validation.samples.validate`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy.typing as npt

from sandlight.physics.medium import OpticalConstants
from sandlight.validation.samples import SAMPLES, run_and_score, sample_by_name
from sandlight.validation.scoring import ValidationResult, model_wavelengths_nm

__all__ = ["Variant", "DIAGNOSTIC_VARIANTS", "run_variants"]


@dataclass(frozen=True)
class Variant:
    """A what-if run of a validation sample: the preset with one physical change.

    Variants are diagnostics, not fits: each tests whether one candidate cause can move the
    model by the size of the observed miss.

    Attributes
    ----------
    sample : str
        Name of the validation sample (:data:`~sandlight.validation.samples.SAMPLES`).
    label : str
        Short name for tables.
    hypothesis : str
        The physics the variant probes.
    changes : Mapping[str, object]
        Sample parameters replaced in the preset (:meth:`SandSample.replace`).
    k_factor : Mapping[str, float]
        Factor applied to a material's extinction coefficient k at λ ≥ ``k_factor_from_nm``.
    k_factor_from_nm : float
        Lower wavelength limit (nm) of ``k_factor``.
    extra_alpha_per_cm : Mapping[str, float]
        Absorption coefficient added to a material at every wavelength (cm⁻¹).
    """

    sample: str
    label: str
    hypothesis: str
    changes: Mapping = field(default_factory=dict)
    k_factor: Mapping = field(default_factory=dict)
    k_factor_from_nm: float = 0.0
    extra_alpha_per_cm: Mapping = field(default_factory=dict)

    @property
    def changes_optics(self) -> bool:
        """Whether the variant changes optical constants (``k_factor`` or ``extra_alpha_per_cm``)."""
        return bool(self.k_factor or self.extra_alpha_per_cm)

    def optical_constants(self) -> OpticalConstants | None:
        """The optical constants of this variant, ``(material, wavelength_nm) -> n + ik``: the
        shipped tables (:func:`sandlight.optics.complex_index`) with ``k_factor`` and
        ``extra_alpha_per_cm`` applied; None when the variant does not change them.

        The shipped tables stay untouched: the variant's medium is built with these constants
        (:class:`sandlight.physics.media.SandMedium`), through the same physics code as the
        validation.
        """
        if not self.changes_optics:
            return None
        from sandlight.optics import complex_index

        def adjusted(material: str, wavelength_nm: float) -> complex:
            m = complex(complex_index(material, wavelength_nm))
            k = m.imag
            if material in self.k_factor and float(wavelength_nm) >= self.k_factor_from_nm:
                k *= self.k_factor[material]
            if material in self.extra_alpha_per_cm:
                # α = 4πk/λ, so an added α (cm⁻¹) is k = αλ/(4π) with λ in cm (nm × 1e-7).
                k += self.extra_alpha_per_cm[material] * float(wavelength_nm) * 1e-7 / (4.0 * math.pi)
            return complex(m.real, k)

        return adjusted


_GDS76 = SAMPLES[0].name
_OTTAWA = SAMPLES[1].name

DIAGNOSTIC_VARIANTS: tuple[Variant, ...] = (
    Variant(
        _GDS76,
        "no hematite (the quartz host alone)",
        "ceiling: what the quartz host gives with no absorber",
        {"iron_oxide": 0.0},
    ),
    Variant(
        _GDS76,
        "hematite k × 0.2 at λ ≥ 580 nm",
        "hematite's absorption edge is steeper than the log-linear join of Querry and Longtin",
        k_factor={"hematite": 0.2},
        k_factor_from_nm=580.0,
    ),
    Variant(
        _GDS76,
        "hematite particles 1 µm",
        "finer primary hematite grains (more cross-section per mass)",
        {"iron_oxide_particle_size_um": 1.0},
    ),
    Variant(
        _GDS76,
        "hematite particles 10 µm",
        "partial aggregation of the 2–3 µm hematite grains",
        {"iron_oxide_particle_size_um": 10.0},
    ),
    Variant(
        _GDS76,
        "hematite as a uniform coating",
        "the hematite smeared over the quartz grains instead of separate particles",
        {"iron_oxide_form": "coating", "coating_iron_share": 1.0},
    ),
    Variant(_GDS76, "no silt (fines)", "fewer quartz fines", {"sand": 1.0, "silt": 0.0}),
    Variant(
        _GDS76, "quartz host + 1 cm⁻¹", "absorption of the quartz host (impurities)", extra_alpha_per_cm={"quartz": 1.0}
    ),
    Variant(_OTTAWA, "grain size 0.2 mm", "the unknown grade: finer sand", {"grain_size": 0.2}),
    Variant(_OTTAWA, "grain size 0.8 mm", "the unknown grade: coarser sand", {"grain_size": 0.8}),
    Variant(_OTTAWA, "depth 5 mm over a black bottom", "a shallow sample cup", {"depth_mm": 5.0}),
    Variant(
        _OTTAWA,
        "quartz host + 1 cm⁻¹",
        "grey absorption of the quartz host (inclusions, impurities)",
        extra_alpha_per_cm={"quartz": 1.0},
    ),
    Variant(
        _OTTAWA,
        "0.01 wt% iron oxide coating",
        "trace iron staining (hematite/goethite 1:1 in the default kaolinite coating)",
        {"iron_oxide": 0.0001, "hematite_ratio": 0.5, "iron_oxide_form": "coating"},
    ),
)


def run_variants(
    variants: Sequence[Variant] = DIAGNOSTIC_VARIANTS,
    *,
    rays: int,
    wavelengths_nm: npt.ArrayLike | None = None,
    seed: int = 0,
    progress: bool = False,
) -> list[ValidationResult]:
    """Runs and scores diagnostic variants (:class:`Variant`) like
    :func:`~sandlight.validation.samples.validate` does."""
    from sandlight.physics.media import SandMedium
    from sandlight.sample import SandSample

    wl = model_wavelengths_nm(wavelengths_nm)
    spectra = {}
    results = []
    for v in variants:
        s = sample_by_name(v.sample)
        if s.name not in spectra:
            spectra[s.name] = s.measured_spectrum()
        sample = SandSample.preset(s.preset).replace(**dict(v.changes))
        traced = SandMedium.from_sample(sample, optical_constants=v.optical_constants())
        results.append(
            run_and_score(
                s, traced, v.label, spectra[s.name], rays=rays, wavelengths_nm=wl, seed=seed, progress=progress
            )
        )
    return results
