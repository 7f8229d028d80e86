"""Spectra in and out as colour-science's SpectralDistribution (issue 24, interoperability)."""

import numpy as np
import pytest
import xarray as xr

import colour
import sandlight
from sandlight.colour import (
    PREDICTOR_WAVELENGTHS_NM,
    from_spectral_distribution,
    spectrum_to_xyz,
    to_spectral_distribution,
)
from sandlight.errors import ParameterError


def test_a_monte_carlo_spectrum_round_trips_through_a_spectral_distribution():
    result = sandlight.reflectance("red-dune", PREDICTOR_WAVELENGTHS_NM, rays=2000, progress=False)
    sd = to_spectral_distribution(result)
    assert isinstance(sd, colour.SpectralDistribution)
    wavelengths, values = from_spectral_distribution(sd)
    np.testing.assert_array_equal(wavelengths, result.wavelengths)
    np.testing.assert_array_equal(values, result.values)
    # sandlight's integration takes the distribution as it takes the arrays
    np.testing.assert_array_equal(spectrum_to_xyz(sd), spectrum_to_xyz(result.wavelengths, result.values))


@pytest.mark.filterwarnings("ignore:.*is not uniform")  # colour-science aligning an irregular grid
def test_an_irregular_measured_spectrum_keeps_its_wavelengths():
    wl = np.array([350.0, 400.0, 455.0, 610.0, 700.0, 2500.0])
    measured = xr.DataArray(np.linspace(0.1, 0.6, wl.size), dims="wavelength", coords={"wavelength": wl})
    sd = to_spectral_distribution(measured, name="USGS sample")
    assert sd.name == "USGS sample" and sd.wavelengths.tolist() == wl.tolist()
    # colour-science's own integration runs on it (it interpolates to its grid itself)
    assert colour.sd_to_XYZ(sd.copy().align(colour.SpectralShape(360, 780, 1))).shape == (3,)


@pytest.mark.parametrize(
    ("args", "name"),
    [
        (([400, 300], [0.1, 0.2]), "wavelengths"),
        (([400, 500], [0.1]), "values"),
        (("not a spectrum",), "spectrum"),
    ],
)
def test_bad_spectra_are_refused_with_a_message(args, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        to_spectral_distribution(*args)
    with pytest.raises(ParameterError, match="^sd = "):
        from_spectral_distribution(np.ones(3))
