"""Tests of the `sandlight validate` command: the report and figures, and bad options."""


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
