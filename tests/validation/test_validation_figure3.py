"""Tests of sandlight.validation.figure3: the paper's Figure 3 from the model."""

import numpy as np

from sandlight import validation as v

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_figure3_spectra_order_and_plot(tmp_path):
    spectra = v.figure3_spectra(rays=300, wavelengths_nm=[450.0, 900.0], seed=1)
    quartz = spectra["quartz"].values
    for mineral in ("hematite", "goethite"):
        powder, mixture = spectra[mineral]["powder"], spectra[mineral]["mixture"]
        assert powder.sample["material"] == mineral and powder.sample["diameter_um"] == [v.FIGURE3_PARTICLE_UM]
        # At 450 nm the pure iron oxide is the darkest, the quartz the brightest, the mixture between.
        assert powder.values[0] < mixture.values[0] < quartz[0]
    np.testing.assert_array_equal(spectra["wavelengths_nm"], [450.0, 900.0])
    path = tmp_path / "figure3.png"
    v.plot_figure3(spectra, path, measured=False)
    assert path.read_bytes()[:8] == PNG_SIGNATURE
