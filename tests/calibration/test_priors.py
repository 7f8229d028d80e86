"""sandlight.calibration.priors: the literature curves are where their sources put them."""

import math

import numpy as np
import pytest

from sandlight import calibration as cal
from sandlight.errors import ParameterError


def test_goethite_prior_has_its_edge_and_crystal_field_bands():
    wl = np.arange(350.0, 2501.0, 5.0)
    k = cal.goethite_literature_k(wl)
    # Charge-transfer edge: k ~ 0.6 in the blue, ~0.09 at 550 nm (Bedidi & Cervelle 1993).
    assert k[wl == 400.0][0] == pytest.approx(0.6, rel=0.05)
    assert 0.05 < cal.goethite_literature_k(550.0) < 0.12
    # The 4T1 band: a local maximum of k between 850 and 1000 nm (925 nm, Scheinost et al. 1998).
    red = (wl >= 750) & (wl <= 1200)
    assert 850.0 <= wl[red][np.argmax(k[red])] <= 1000.0
    np.testing.assert_array_equal(cal.literature_k("goethite", wl), k)


def test_quartz_prior_is_the_natural_grain_absorption_law():
    alpha_per_cm = 4 * math.pi * cal.quartz_literature_k(550.0) / 550e-7
    assert alpha_per_cm == pytest.approx(0.1, rel=1e-12)
    assert cal.quartz_literature_k(400.0) > cal.quartz_literature_k(700.0)


def test_minerals_without_a_prior_and_bad_wavelengths_are_refused():
    with pytest.raises(ParameterError, match="mineral"):
        cal.literature_k("hematite", 500.0)
    with pytest.raises(ParameterError, match="wavelength_nm"):
        cal.goethite_literature_k([500.0, -1.0])
