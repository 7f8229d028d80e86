"""sandlight.calibration.with_calibrated_k: the shipped constants with a calibrated k."""

import numpy as np
import pytest
from conftest import REPO

from sandlight.calibration import read_k_table, with_calibrated_k
from sandlight.errors import ModelFileError
from sandlight.optics import complex_index

QUARTZ_K = REPO / "docs" / "calibration" / "quartz" / "quartz-k.csv"


def test_the_calibrated_minerals_k_replaces_the_shipped_one_and_nothing_else():
    index = with_calibrated_k({"quartz": QUARTZ_K})
    _, wl, _, k = read_k_table(QUARTZ_K)
    for w, kw in zip(wl[::7], k[::7]):
        m = index("quartz", float(w))
        assert m.imag == pytest.approx(kw, rel=1e-12)  # at a calibration wavelength: the table's value
        assert m.real == complex(complex_index("quartz", float(w))).real
    assert index("hematite", 550.0) == complex(complex_index("hematite", 550.0))
    between = 0.5 * (wl[3] + wl[4])  # log-linear between table points
    assert index("quartz", float(between)).imag == pytest.approx(np.sqrt(k[3] * k[4]), rel=1e-9)


def test_a_table_of_another_mineral_is_refused_with_its_path():
    with pytest.raises(ModelFileError, match="quartz-k.csv"):
        with_calibrated_k({"goethite": QUARTZ_K})
