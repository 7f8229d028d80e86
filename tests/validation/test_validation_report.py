"""Tests of sandlight.validation.report: the Markdown report, written and updated."""

import pytest

from sandlight import validation as v
from sandlight.errors import ParameterError


@pytest.fixture(scope="module")
def results():
    return v.validate(rays=200, wavelengths_nm=[450.0, 550.0, 650.0, 1000.0, 2000.0], seed=1)


def test_report_writer_sections_and_update_keeps_hand_written_text(results, tmp_path):
    report = tmp_path / "docs" / "validation.md"
    figs = [tmp_path / "docs" / "img" / f"{r.sample.preset}.png" for r in results]
    v.write_report(report, results, figure_paths=figs, command="sandlight validate --rays 300")
    text = report.read_text(encoding="utf-8")
    for heading in (
        "# Validation against measured spectra",
        "## How to reproduce",
        "## Results",
        "## Spectra",
        "## Diagnostic variants",
        "## The paper's Figure 3, from the model",
    ):
        assert heading in text
    for name in v.REPORT_BLOCKS:
        assert f"<!-- BEGIN validation:{name} -->" in text and f"<!-- END validation:{name} -->" in text
    assert "sandlight validate --rays 300" in text
    assert "(img/gds76-hematite-quartz.png)" in text
    assert "preset `gds76-hematite-quartz`" in text
    for r in results:
        for e in r.errors.values():
            assert f"| {r.sample.name} | {e.band} | {e.rms:.4f} ± {e.rms_mc:.4f} |" in text

    # A hand-written discussion outside the blocks survives an update; the blocks change.
    report.write_text(text + "\n## Discussion\n\nHand-written.\n", encoding="utf-8")
    v.write_report(report, results, figure_paths=figs, command="sandlight validate --rays 999")
    updated = report.read_text(encoding="utf-8")
    assert "## Discussion\n\nHand-written." in updated
    assert "--rays 999" in updated and "--rays 300" not in updated
    with pytest.raises(ParameterError, match="figure_paths"):
        v.write_report(report, results, figure_paths=figs[:1], command="x")
