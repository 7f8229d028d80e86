"""The spectral × spatial combination: energy conservation, the product where r ≤ r_0, exact albedo."""

import numpy as np
import pytest
from appearance_helpers import directions, from_angles, hemisphere_quadrature, shipped

from sandlight.appearance import SandAppearance
from sandlight.sample import SandSample


@pytest.mark.parametrize("preset", SandSample.presets())
def test_albedo_at_most_one_at_every_incidence_for_every_preset(preset, spectral, spatial):
    app = SandAppearance(preset, spectral, spatial, fixed="ignore")
    wi = from_angles(np.linspace(0, 90, 181)[:, None] * np.ones((1, 1)))[:, 0]
    albedo = app.albedo(wi)
    assert (albedo >= 0).all() and (albedo <= 1 + 1e-12).all()
    # At normal incidence the albedo is the spectral prediction (paper §3.3).
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], app.normal_reflectance, atol=1e-12)


def test_bright_spectrum_stays_energy_conserving(app, product):
    grazing = from_angles(89.9)
    assert app.albedo(grazing).max() <= 1 + 1e-12
    # The paper's product would reflect more than arrives at grazing incidence for this spectrum.
    assert product.albedo(grazing).max() > 1.2
    # Both reproduce r(λ) at normal incidence, and agree where r ≤ r_0.
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], product.albedo([0, 0, 1])[0], atol=1e-12)


def test_energy_combination_equals_the_product_for_darker_spectra(spatial):
    dark = lambda s: (np.arange(400.0, 701.0, 20.0), np.full(16, 0.05))  # noqa: E731
    a = SandAppearance(SandSample(saturation=0.3), dark, spatial)
    b = SandAppearance(SandSample(saturation=0.3), dark, spatial, combination="product")
    assert a.reference_reflectance > 0.05
    wi, wo = directions(500, 1), directions(500, 2)
    np.testing.assert_array_equal(a.brdf(wi, wo), b.brdf(wi, wo))


@pytest.mark.parametrize("theta", [0.0, 30.0, 60.0, 80.0, 89.0])
def test_albedo_equals_the_integral_of_the_brdf(app, theta):
    d, w = hemisphere_quadrature()
    wi = from_angles(theta, 20.0)
    f = app.brdf(wi, d)
    integral = (f * d[:, 2:3] * w[:, None]).sum(axis=0)
    np.testing.assert_allclose(integral, app.albedo(wi)[0], rtol=2e-3)


@shipped
@pytest.mark.parametrize("preset", SandSample.presets())
def test_shipped_spatial_model_conserves_energy_for_every_preset(preset, spectral):
    app = SandAppearance(preset, spectral, None, fixed="ignore")
    wi = from_angles(np.linspace(0, 90, 181))
    albedo = app.albedo(wi)
    assert (albedo >= 0).all() and (albedo <= 1 + 1e-12).all()
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], app.normal_reflectance, atol=1e-12)
