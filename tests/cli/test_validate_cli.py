"""sandlight validate writes a new folder in the working directory by default, never the docs."""

from typer.testing import CliRunner

from sandlight.cli import app


def test_validate_writes_into_a_new_folder_by_default(tmp_path, monkeypatch):
    # Run from a checkout it overwrote ./docs/validation.md and ./docs/img/.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "docs").mkdir()
    args = ["validate", "--rays", "200", "--no-variants", "--sample", "Hematite.02+Quartz.98_GDS76"]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    report = tmp_path / "sandlight-validation" / "validation.md"
    figure = tmp_path / "sandlight-validation" / "img" / "validation-gds76-hematite-quartz.png"
    assert report.is_file() and figure.is_file()
    assert "img/validation-gds76-hematite-quartz.png" in report.read_text(encoding="utf-8")
    assert list((tmp_path / "docs").iterdir()) == []


def test_cli_validate_writes_report_and_figures(tmp_path):
    from typer.testing import CliRunner

    from sandlight.cli import app

    out = tmp_path / "validation.md"
    res = CliRunner().invoke(
        app,
        [
            "validate",
            "--rays",
            "200",
            "--no-variants",
            "--sample",
            "Hematite.02+Quartz.98_GDS76",
            "-o",
            str(out),
            "--figures",
            str(tmp_path / "img"),
        ],
    )
    assert res.exit_code == 0, res.output
    assert (tmp_path / "img" / "validation-gds76-hematite-quartz.png").is_file()
    text = out.read_text(encoding="utf-8")
    assert "--no-variants" in text and "Quartz_GDS74_Sand_Ottawa |" not in text
    bad = CliRunner().invoke(app, ["validate", "--rays", "0", "-o", str(out)])
    assert bad.exit_code == 2 and "--rays" in bad.output
