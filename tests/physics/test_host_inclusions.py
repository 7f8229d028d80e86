"""Inclusions in the quartz host grains (``SandSample.host_scattering``, docs/model.md §2.4)."""

from __future__ import annotations

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.physics.powder import Powder


def _reflectance(sample, wavelengths, rays=6000):
    r = sandlight.reflectance(sample, wavelengths, rays=rays, seed=3, progress=False)
    return r.values, r.stderr


def test_inclusions_brighten_a_clear_quartz_sand():
    # Isotropic inclusions turn the forward-scattering clear grains into diffuse scatterers, so
    # less light is lost deep in the sand (ottawa-gds74 at 650 nm, 4000 rays: 0.498 clear,
    # 0.657 at 10 mm⁻¹); the Ottawa preset's weak host absorption is all there is to lose it to.
    wl = [450.0, 650.0]
    ottawa = sandlight.SandSample.preset("ottawa-gds74")
    clear, se_clear = _reflectance(ottawa, wl)
    milky, se_milky = _reflectance(ottawa.replace(host_scattering=10.0), wl)
    assert np.all(milky - clear > 4 * np.hypot(se_clear, se_milky)), (clear, milky)


def test_no_inclusions_is_the_clear_grain_engine():
    # 0 draws no random number: the default sample is traced exactly as before the parameter.
    s = sandlight.SandSample.preset("red-dune")
    a = sandlight.reflectance(s, [550.0], rays=2000, seed=5, progress=False)
    b = sandlight.reflectance(s.replace(host_scattering=0.0), [550.0], rays=2000, seed=5, progress=False)
    c = sandlight.reflectance(s.replace(host_scattering=1e-9), [550.0], rays=2000, seed=5, progress=False)
    assert np.array_equal(a.values, b.values)
    # A vanishing σ still draws the free paths, so the random numbers differ.
    assert not np.array_equal(a.values, c.values)


def test_bad_inclusions_are_refused_by_name():
    with pytest.raises(ParameterError, match="host_scattering"):
        sandlight.SandSample(host_scattering=-1.0)
    with pytest.raises(ParameterError, match="host_scattering"):
        sandlight.SandSample(host_scattering=1000.0)
    with pytest.raises(ParameterError, match="scattering_per_mm"):
        Powder("hematite", 10.0, scattering_per_mm=-1.0)
    assert Powder("hematite", 100.0, scattering_per_mm=2.0).describe()["scattering_per_mm"] == 2.0
    assert "scattering_per_mm" not in Powder("hematite", 100.0).describe()
