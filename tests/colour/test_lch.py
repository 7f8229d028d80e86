"""sandlight.colour.lch: L*, C*ab, h° of spectra and the propagated error of C*ab."""

from __future__ import annotations

import numpy as np
import pytest

from sandlight.colour.lch import lch, lch_with_chroma_error

WL = np.arange(400.0, 701.0, 20.0)


def test_a_grey_spectrum_has_the_lightness_of_its_reflectance_and_no_chroma():
    lightness, chroma, _ = lch(WL, np.full(WL.size, 0.5))
    assert lightness == pytest.approx(116 * 0.5 ** (1 / 3) - 16, abs=1e-6)
    assert chroma < 1e-3


def test_the_chroma_error_is_the_spread_of_chroma_over_noisy_spectra():
    # A reddish spectrum with independent noise σ per wavelength: the linearised σ(C*) against
    # the standard deviation of C* over 4000 noisy copies (its own relative error ~1.1 %).
    r = np.linspace(0.1, 0.7, WL.size)
    sigma = 0.003
    _, c, _, se = lch_with_chroma_error(WL, r, sigma**2 * np.eye(WL.size))
    rng = np.random.default_rng(1)
    chromas = [lch(WL, r + sigma * rng.standard_normal(WL.size))[1] for _ in range(4000)]
    assert np.mean(chromas) == pytest.approx(c, abs=4 * se / np.sqrt(4000) + 1e-3)
    assert np.std(chromas) == pytest.approx(se, rel=4 * 0.0112)
    assert lch_with_chroma_error(WL, r, np.zeros((WL.size, WL.size)))[3] == 0.0
