"""The band grid of the spatial part: quadrature weights, mirror symmetry, normalisation, the cap's step."""

import math

import numpy as np
import pytest
from appearance_helpers import directions, hemisphere_quadrature, shipped

from sandlight.appearance import SandAppearance
from sandlight.sample import SandSample


def test_continuous_brdf_is_normalised_at_normal_incidence(product):
    d, w = hemisphere_quadrature()
    f = product.brdf([0, 0, 1], d, [550.0])[:, 0] / product.reflectance_at([550.0])[0]
    assert (f * d[:, 2] * w).sum() == pytest.approx(1.0, rel=2e-3)


def test_isotropy_and_mirror_symmetry(app):
    wi, wo = directions(1000, 5), directions(1000, 6)
    a = app.brdf(wi, wo)
    angle = 1.234
    rot = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    np.testing.assert_allclose(app.brdf(wi @ rot.T, wo @ rot.T), a, rtol=1e-10)
    mirror = np.diag([1.0, -1.0, 1.0])
    np.testing.assert_allclose(app.brdf(wi @ mirror, wo @ mirror), a, rtol=1e-10)


@shipped
@pytest.mark.parametrize("saturation", [0.0, 0.5, 1.0])
def test_normal_incidence_peak_does_not_rescale_the_brdf(saturation):
    # Saturated sand has a narrow mirror peak back towards normal incidence (flat water). The
    # continuous BRDF keeps the measured values elsewhere: at normal incidence, its values at the
    # outgoing band centroids equal the spatial prediction's patch values (Δφ-independent there).
    flat = lambda s: (np.arange(400.0, 701.0, 20.0), np.full(16, 0.5))  # noqa: E731
    app = SandAppearance(SandSample(saturation=saturation), flat, None, combination="product")
    h = app.spatial.hemisphere
    bands = 1 + h.slices * np.arange(h.n_bands)  # first patch of every band
    f = app.brdf([0, 0, 1], h.centroids[bands], [550.0])[:, 0] / 0.5
    np.testing.assert_allclose(f, app.spatial.values[h.cap, bands], rtol=0.05)
    # and the albedo at normal incidence is exactly the spectral value.
    assert app.albedo([0, 0, 1], [550.0])[0, 0] == pytest.approx(0.5, abs=1e-12)
