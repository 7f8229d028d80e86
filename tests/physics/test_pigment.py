"""The pigmented coating (sandlight.physics.pigment) and the engine's coating_optics='mie'.

Coefficients against miepython (Prahl), an independent Lorenz–Mie code (m = n − ik there, so
sandlight's index is conjugated; docs in tests/physics/test_mie.py). Engine checks use fixed
seeds, tolerances from the Monte Carlo error (4 standard errors).
"""

from __future__ import annotations

import numpy as np
import pytest

import sandlight
from sandlight import _native
from sandlight.colour.lch import lch_with_chroma_error
from sandlight.errors import ParameterError
from sandlight.optics import complex_index
from sandlight.physics.composition import compose
from sandlight.physics.media import SandMedium
from sandlight.physics.pigment import PIGMENT_DIAMETER_UM, coating_optics
from sandlight.sample import SandSample

miepython = pytest.importorskip("miepython", minversion="3.3")

RAYS = 80_000
COATING = {"hematite": 0.2, "goethite": 0.1, "kaolinite": 0.7}


@pytest.mark.parametrize("diameter_um", [0.1, 0.4])
@pytest.mark.parametrize("wavelength_nm", [450.0, 650.0])
def test_coefficients_are_those_of_miepython_cross_sections(diameter_um, wavelength_nm):
    kaol = complex(complex_index("kaolinite", wavelength_nm))
    x = np.pi * diameter_um * 1000.0 * kaol.real / wavelength_nm
    alpha = sca = sca_g = 0.0
    for name in ("hematite", "goethite"):
        m = complex(complex_index(name, wavelength_nm)) / kaol.real
        q_ext, q_sca, _, g = miepython.efficiencies_mx(np.conj(m), x)
        v = COATING[name]
        # Per unit volume: N C = (3/2) v Q / d.
        alpha += 1.5 * v * (q_ext - q_sca) / (diameter_um * 1e-3)
        sca += 1.5 * v * q_sca / (diameter_um * 1e-3)
        sca_g += 1.5 * v * q_sca * g / (diameter_um * 1e-3)
    alpha += 0.7 * 4 * np.pi * kaol.imag / (wavelength_nm * 1e-6)
    c = coating_optics(COATING, wavelength_nm, diameter_um)
    assert c.n == kaol.real
    assert c.absorption_per_mm == pytest.approx(alpha, rel=1e-7)
    assert c.scattering_per_mm == pytest.approx(sca, rel=1e-7)
    assert c.asymmetry == pytest.approx(sca_g / sca, rel=1e-7)


def test_bad_coatings_and_sizes_are_refused():
    with pytest.raises(ParameterError, match="coating"):
        coating_optics({"quartz": 1.0}, 550.0)
    with pytest.raises(ParameterError, match="pigment_diameter_um"):
        coating_optics(COATING, 550.0, 0.0)
    with pytest.raises(ParameterError, match="coating_optics"):
        SandMedium(compose(SandSample()), coating_optics="paint")


def _chroma_and_stderr(result):
    _, c, _, se = lch_with_chroma_error(result.wavelengths, result.values, result.covariance)
    return c, se


def test_zero_scattering_through_the_binding_reproduces_the_uniform_coating(monkeypatch):
    # The native medium given explicit zero scattering (and any asymmetry) traces exactly as
    # the uniform coating: same decisions from the same random numbers.
    from sandlight.physics import medium as medium_module

    wl = [450.0, 600.0]
    sample = SandSample.preset("red-dune")
    before = sandlight.reflectance(sample, wl, rays=3000, seed=3, progress=False)

    class Shim:
        class Medium:
            @staticmethod
            def particulate(*args, **kwargs):
                n = len(args[0])
                return _native.Medium.particulate(
                    *args, **kwargs, coating_scattering_per_mm=[0.0] * n, coating_asymmetry=[0.5] * n
                )

    monkeypatch.setattr(medium_module, "_native", Shim)
    after = sandlight.reflectance(sample, wl, rays=3000, seed=3, progress=False)
    np.testing.assert_array_equal(after.values, before.values)


def test_without_a_coating_the_mie_option_changes_nothing():
    sample = SandSample.preset("gds76-hematite-quartz")  # iron oxide as separate particles
    assert sample.iron_oxide_form == "particles"
    wl = [450.0, 650.0]
    a = sandlight.reflectance(SandMedium.from_sample(sample), wl, rays=2000, seed=5, progress=False)
    mie = SandMedium.from_sample(sample, coating_optics="mie")
    b = sandlight.reflectance(mie, wl, rays=2000, seed=5, progress=False)
    np.testing.assert_array_equal(a.values, b.values)


def test_a_lossless_pigmented_sand_loses_no_light():
    # Every material made non-absorbing: the scattering coating's diffuse parts conserve
    # energy, so every ray that is not capped escapes a semi-infinite sample.
    def real_only(material, wavelength_nm):
        return complex(complex(complex_index(material, wavelength_nm)).real)

    sample = SandSample.preset("red-dune")
    med = SandMedium.from_sample(sample, optical_constants=real_only, coating_optics="mie", pigment_diameter_um=0.3)
    # Scattering optical depth of the coating: appreciable (the test would be empty otherwise).
    pop = med.composition.populations[0]
    c = coating_optics(pop.coating, 550.0, 0.3, optical_constants=real_only)
    assert c.absorption_per_mm == 0.0 and c.scattering_per_mm * pop.coating_thickness_mm > 0.2
    r = sandlight.reflectance(med, [550.0], rays=300, seed=7, max_events=20_000, progress=False)
    launched, capped = int(r.counts["launched"][0]), int(r.counts["capped"][0])
    assert r.values[0] == pytest.approx(1.0 - capped / launched, abs=1e-12)


# yellow-dune at the default crystal size; red-dune at 0.3 µm, because at the default 0.1 µm
# its Mie coating measured C* 74.7 ± 1.3 against the uniform 75.3 ± 1.2 (6000 rays): no
# difference the test could resolve (docs/model.md §2.4, "Pigmented coating (Mie)").
@pytest.mark.parametrize(("preset", "diameter_um"), [("yellow-dune", PIGMENT_DIAMETER_UM), ("red-dune", 0.3)])
def test_the_mie_coating_is_less_chromatic_than_the_uniform_one(preset, diameter_um):
    # 80 000 rays: C* ± ~0.4 each, against differences of 4.6 (yellow) and 23 (red) with the
    # default engine (measured 2026-12-06: 79.5 vs 74.9, 64.9 vs 41.6).
    wl = np.arange(400.0, 701.0, 20.0)
    sample = SandSample.preset(preset)
    uniform = sandlight.reflectance(SandMedium.from_sample(sample), wl, rays=RAYS, seed=11, progress=False)
    mie_medium = SandMedium.from_sample(sample, coating_optics="mie", pigment_diameter_um=diameter_um)
    mie = sandlight.reflectance(mie_medium, wl, rays=RAYS, seed=12, progress=False)
    (cu, su), (cm, sm) = _chroma_and_stderr(uniform), _chroma_and_stderr(mie)
    assert cu - cm > 4 * np.hypot(su, sm), f"uniform C* {cu:.1f} ± {su:.2f}, mie {cm:.1f} ± {sm:.2f}"
