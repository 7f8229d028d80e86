"""SandSample.host_absorption: a factor on the quartz host's k, applied where the native medium
is built (sandlight.physics.medium.with_host_absorption); the sand darkens as it grows."""

import numpy as np
import pytest

from sandlight import SandSample, reflectance
from sandlight.errors import ParameterError
from sandlight.optics import complex_index
from sandlight.physics.composition import compose
from sandlight.physics.medium import with_host_absorption

QUARTZ_SAND = SandSample.preset("ottawa-gds74")  # pure quartz, 0.4 mm grains, no iron oxide
RAYS = 2000


def test_the_factor_scales_the_quartz_k_only():
    index = with_host_absorption(complex_index, 3.0)
    q = complex(complex_index("quartz", 550.0))
    assert index("quartz", 550.0) == pytest.approx(complex(q.real, 3.0 * q.imag), rel=1e-12)
    assert index("hematite", 550.0) == complex(complex_index("hematite", 550.0))
    assert with_host_absorption(complex_index, 1.0) is complex_index
    assert compose(QUARTZ_SAND.replace(host_absorption=2.5)).host_absorption == 2.5


def test_reflectance_falls_monotonically_with_host_absorption():
    # Blue wavelengths, where the host's k is largest (with the literature k of the shipped table,
    # k(1000 nm) ≈ 1e-7 darkens 0.4 mm grains by less than 4 standard errors at these rays).
    wavelengths = [400.0, 450.0]
    factors = (0.3, 1.0, 3.0, 10.0)
    runs = [
        reflectance(QUARTZ_SAND.replace(host_absorption=f), wavelengths, rays=RAYS, seed=7, progress=False)
        for f in factors
    ]
    values = np.array([r.values for r in runs])
    stderr = np.array([r.stderr for r in runs])
    # Each step darkens the sand by more than 4 standard errors of the difference.
    drop = values[:-1] - values[1:]
    assert np.all(drop > 4.0 * np.hypot(stderr[:-1], stderr[1:])), values


def test_out_of_domain_factor_is_refused_with_its_name():
    with pytest.raises(ParameterError, match="host_absorption"):
        SandSample(host_absorption=11.0)
    with pytest.raises(ParameterError, match="host_absorption"):
        SandSample(host_absorption=-0.1)
