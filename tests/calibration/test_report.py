"""sandlight.calibration.report: identifiability, Markdown, figure and the derived k table."""

import numpy as np
import pytest
from calibration_fakes import FakePowder

from sandlight import calibration as cal
from sandlight.errors import ModelFileError

WL = np.array([400.0, 500.0, 700.0, 1000.0, 1500.0, 2000.0, 2500.0])
GRID = np.arange(-7.0, 0.51, 0.25)
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def setup():
    members = cal.end_members("hematite", ids=["GDS69.a", "GDS69.g"])
    tables = [cal.tabulate(m, FakePowder(rays=10**6), WL, GRID) for m in members]
    # Opaque at 400 nm, translucent at 1000 nm, nearly transparent at 2500 nm.
    truth = np.array([0.0, -1.0, -2.5, -3.0, -3.5, -4.0, -6.9])
    values, sigma = cal.synthetic_spectra(FakePowder(rays=10**6, seed=1), members, WL, truth, sigma=0.002, seed=2)
    fit = cal.KFit().fit(tables, values, sigma)
    return tables, fit, values, sigma, cal.identifiability(tables, fit.log10_k_, sigma)


def test_identifiability_tells_opaque_from_translucent_from_transparent(setup):
    tables, fit, values, sigma, ident = setup
    assert list(ident.state[:, 0]) == ["opaque", "opaque"]
    assert not ident.identifiable[0]
    assert ident.identifiable[3] and list(ident.state[:, 3]) == ["sees k", "sees k"]
    assert "transparent" in ident.state[:, -1]
    assert not ident.identifiable[-1]
    assert ident.verdict(0) == "not identifiable: 2 opaque"
    assert ident.verdict(3) == "identified by 2 of 2"


def test_sigma_is_the_local_sensitivity_where_rho_is_linear_in_log_k(setup):
    tables, fit, values, sigma, ident = setup
    # σ_s = σ_ρ / |∂ρ/∂log10 k| where k is well determined.
    local = ident.sigma_rho[:, 3] / np.abs(ident.drho_dlog10_k[:, 3])
    np.testing.assert_allclose(ident.sigma_log10_k[:, 3], local, rtol=0.1)
    combined = 1.0 / np.sqrt(np.sum(1.0 / local**2))
    assert ident.combined_sigma_log10_k[3] == pytest.approx(combined, rel=0.1)


def test_markdown_tables(setup):
    tables, fit, values, sigma, ident = setup
    text = cal.markdown_residuals(fit, held_out={"GDS69.x": (fit.fitted_[0], values[0])})
    assert text.count("\n") == 4  # header, rule, two fitted rows, one predicted
    assert "| GDS69.x | **predicted** |" in text
    table = cal.markdown_identifiability(ident, fit, [400, 1000, 2500], with_model=ident)
    rows = table.splitlines()
    assert len(rows) == 5 and rows[2].startswith("| 400 |") and "opaque" in rows[2]
    assert all(row.count("|") == rows[0].count("|") for row in rows)


def test_figure_and_k_table(setup, tmp_path):
    tables, fit, values, sigma, ident = setup
    cal.plot_calibration(
        tmp_path / "k.png", fit, values, ident, mineral="hematite", errors="test errors", truth=(WL, 10**fit.log10_k_)
    )
    assert (tmp_path / "k.png").read_bytes()[:8] == PNG_SIGNATURE
    cal.write_k_table(tmp_path / "hematite-k.csv", "hematite", fit, ident, command="a command", inputs="two spectra")
    lines = (tmp_path / "hematite-k.csv").read_text().splitlines()
    header = [line for line in lines if line.startswith("#")]
    assert any("status: derived by calibration" in line for line in header)
    assert any("a command" in line and "RMS residuals" in line for line in header)
    assert lines[len(header)] == "wavelength_nm,n,k"
    data = np.loadtxt(lines[len(header) + 1 :], delimiter=",")
    np.testing.assert_allclose(data[:, 0], WL)
    np.testing.assert_allclose(data[:, 2], fit.k_, rtol=1e-5)
    assert np.all(data[:, 1] > 2.0)  # hematite's n from the shipped table
    # Read back: the header by key, the columns as written.
    read_header, wl, n, k = cal.read_k_table(tmp_path / "hematite-k.csv")
    assert read_header["material"] == "hematite" and read_header["method"].startswith("a command")
    np.testing.assert_array_equal(wl, data[:, 0])
    np.testing.assert_array_equal(k, data[:, 2])
    # A foreign file is refused with its name.
    (tmp_path / "other.csv").write_text("# material: hematite\nwavelength_nm,n,k\n500,2,0.1\n600,2,0.01\n")
    with pytest.raises(ModelFileError, match="other.csv"):
        cal.read_k_table(tmp_path / "other.csv")
