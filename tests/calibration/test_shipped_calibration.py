"""The shipped calibrated k (issue 17 §1): reproducible byte for byte from the committed tables,
and what sandlight.optics serves.

For each mineral of scripts/data/build_optical_tables.py's CALIBRATED, the calibration output
docs/calibration/<m>/<m>-k.csv records its canonical command; rerun from the committed ρ tables
(docs/calibration/<m>/tables, no engine run), it writes the same bytes. The shipped optical table
holds that k (and the shipped n) at every calibration wavelength.
"""

import subprocess
import sys

import numpy as np
import pytest
from conftest import REPO, needs_shared

from sandlight import calibration as cal
from sandlight.optics import complex_index

CALIBRATED = ("quartz", "goethite")
SCRIPT = "python scripts/data/calibrate_optical_constants.py"


def k_csv(mineral):
    return REPO / "docs" / "calibration" / mineral / f"{mineral}-k.csv"


def recorded_command(mineral) -> list[str]:
    """The options of the canonical command in the csv's method line."""
    method = next(line for line in k_csv(mineral).read_text().splitlines() if line.startswith("# method: "))
    command = method.removeprefix("# method: ").split(";")[0]
    assert command.startswith(SCRIPT + " "), command
    return command.removeprefix(SCRIPT + " ").split()


def test_the_build_script_and_these_tests_calibrate_the_same_minerals():
    text = (REPO / "scripts" / "data" / "build_optical_tables.py").read_text()
    assert "CALIBRATED = (" + ", ".join(f'"{m}"' for m in CALIBRATED) + ")" in text


@pytest.mark.parametrize("mineral", CALIBRATED)
def test_shipped_table_is_the_calibrated_k(mineral):
    header, wl, n, k = cal.read_k_table(k_csv(mineral))
    assert header["material"] == mineral
    assert wl[0] == 350.0 and wl[-1] == 2500.0
    m = complex_index(mineral, wl)
    # The shipped table interpolates the csv's k onto its 5 nm grid, which holds every
    # calibration wavelength, and stores 7 significant digits.
    np.testing.assert_allclose(m.imag, k, rtol=1e-6)
    np.testing.assert_allclose(m.real, n, rtol=0, atol=5.1e-6)  # n rounded to 6 digits, n < 10


@pytest.mark.slow
@needs_shared
@pytest.mark.parametrize("mineral", CALIBRATED)
def test_refit_from_the_committed_tables_reproduces_the_k_csv(mineral, tmp_path):
    tables = REPO / "docs" / "calibration" / mineral / "tables"
    result = subprocess.run(
        [sys.executable, "scripts/data/calibrate_optical_constants.py", *recorded_command(mineral)]
        + ["--cache", str(tables), "--out", str(tmp_path), "--threads", "1"],
        capture_output=True,
        text=True,
        cwd=REPO,
    )
    assert result.returncode == 0, result.stderr
    assert "k column" not in result.stderr, "a table was not complete in the committed cache"
    assert (tmp_path / f"{mineral}-k.csv").read_bytes() == k_csv(mineral).read_bytes()
