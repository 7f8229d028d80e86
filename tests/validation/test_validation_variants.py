"""Tests of sandlight.validation.variants: what-if runs change one thing, for their run only."""

import math

import pytest

from sandlight import validation as v


def test_variant_changes_optics_only_for_its_run():
    clear = v.Variant(v.SAMPLES[0].name, "hematite k × 0", "test", k_factor={"hematite": 0.0}, k_factor_from_nm=500.0)
    (preset,) = v.validate([v.SAMPLES[0].name], rays=300, wavelengths_nm=[450.0, 600.0], seed=2)
    (variant,) = v.run_variants([clear], rays=300, wavelengths_nm=[450.0, 600.0], seed=2)
    (after,) = v.validate([v.SAMPLES[0].name], rays=300, wavelengths_nm=[450.0, 600.0], seed=2)
    assert variant.label == "hematite k × 0"
    # Below 500 nm nothing changed and the random streams are shared: identical values.
    assert variant.model[0] == preset.model[0]
    # Without hematite absorption at 600 nm (on its edge) the mixture is brighter, by far more
    # than the noise.
    assert variant.model[1] > preset.model[1] + 5 * preset.model_stderr[1]
    # The shipped optical constants are unchanged after the variant.
    assert list(after.model) == list(preset.model)


def test_variant_optical_constants_scale_k_and_add_absorption():
    from sandlight.optics import complex_index

    assert v.DIAGNOSTIC_VARIANTS[0].optical_constants() is None  # a change of sample parameters only
    edge = v.Variant("x", "edge", "test", k_factor={"hematite": 0.2}, k_factor_from_nm=580.0)
    index = edge.optical_constants()
    shipped = complex(complex_index("hematite", 600.0))
    assert index("hematite", 600.0) == pytest.approx(complex(shipped.real, 0.2 * shipped.imag))
    assert index("hematite", 500.0) == complex(complex_index("hematite", 500.0))
    assert index("quartz", 600.0) == complex(complex_index("quartz", 600.0))
    host = v.Variant("x", "host", "test", extra_alpha_per_cm={"quartz": 1.0})
    added = host.optical_constants()("quartz", 1000.0).imag - complex(complex_index("quartz", 1000.0)).imag
    # α = 4πk/λ: 1 cm⁻¹ at 1000 nm (1e-4 cm) is k = 1e-4/(4π).
    assert added == pytest.approx(1e-4 / (4 * math.pi))


def test_variants_change_the_preset_parameters():
    fine, coarse = (x for x in v.DIAGNOSTIC_VARIANTS if x.label.startswith("grain size"))
    results = v.run_variants([fine, coarse], rays=2000, wavelengths_nm=[550.0, 1500.0], seed=0)
    assert results[0].sample_values["grain_size"] == 0.2 and results[1].sample_values["grain_size"] == 0.8
    # Finer quartz grains scatter more per unit depth: brighter.
    assert results[0].model[0] > results[1].model[0] + 3 * results[0].model_stderr[0]
