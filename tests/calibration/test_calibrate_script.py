"""scripts/data/calibrate_optical_constants.py: documented, refuses bad options cleanly, and runs
end to end at a tiny size (hematite: fit, identifiability, GDS69 cross-validation, round trip)."""

import subprocess
import sys

import pytest
from conftest import REPO, needs_shared

SCRIPT = REPO / "scripts" / "data" / "calibrate_optical_constants.py"


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)


def test_help_documents_the_options_and_the_size():
    result = run("--help")
    assert result.returncode == 0
    options = ("--mineral", "--scale", "--cache", "--out", "--round-trip", "--threads", "--model-sigma")
    for option in (*options, "--grain-scattering", "--min-size-um", "--shipped-prior"):
        assert option in result.stdout
    assert "rays per engine run: 20000 s" in result.stdout


def test_bad_options_give_a_message_not_a_traceback():
    cases = (
        (("--scale", "2"), "--scale"),
        (("--model-sigma", "x"), "--model-sigma"),
        (("--grain-scattering", "-1"), "--grain-scattering"),
        (("--min-size-um", "nan"), "--min-size-um"),
        (("--mineral", "goethite", "--shipped-prior"), "--shipped-prior"),
    )
    for args, name in cases:
        result = run(*args)
        assert result.returncode == 2
        assert name in result.stderr and "not allowed" in result.stderr
        assert "Traceback" not in result.stderr


@pytest.mark.slow
@needs_shared
def test_tiny_hematite_calibration_end_to_end(tmp_path):
    out = tmp_path / "out"
    result = run("--scale", "0.01", "--round-trip", "--cache", str(tmp_path / "cache"), "--out", str(out))
    assert result.returncode == 0, result.stderr
    report = (out / "report.md").read_text()
    for heading in ("## Residuals", "## Identifiability of k", "## Cross-validation", "## Synthetic round trip"):
        assert heading in report
    assert "| GDS69.d | **predicted** |" in report
    assert (out / "hematite-k.csv").read_text().startswith("# material: hematite\n# status: derived by calibration")
    for figure in ("hematite.png", "hematite-round-trip.png"):
        assert (out / figure).stat().st_size > 10_000
    # A second run finds every table in the cache.
    again = run("--scale", "0.01", "--cache", str(tmp_path / "cache"), "--out", str(out))
    assert "k column" not in again.stderr
    # Without the wave-optics powders (from the same tables): GDS27 and GDS69.g are reported as
    # left out, the cross-validation trains on a, c, e, and the shipped k is the prior.
    coarse = tmp_path / "coarse"
    result = run("--scale", "0.01", "--cache", str(tmp_path / "cache"), "--out", str(coarse), "--min-size-um", "10",
                 "--shipped-prior")  # fmt: skip
    assert result.returncode == 0, result.stderr
    report = (coarse / "report.md").read_text()
    assert "fit on GDS69.a, GDS69.c, GDS69.e only" in report
    assert report.count("no: grains all ≤ 10 µm (--min-size-um)") == 2
    assert "--shipped-prior --prior-sigma 1" in report and "--min-size-um 10" in report
