"""Swatch grids: spec parsing, grid order, Figures 6 and 7, PNG output, the swatches command."""

import numpy as np
import pytest
from colour_fakes import FakeSample
from PIL import Image
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.colour import figure6, figure7, parse_grid_spec, sample_rgb, swatch_grid
from sandlight.colour.swatches import framed_size_px
from sandlight.errors import ParameterError


class TestGridSpec:
    def test_inclusive_linspace(self):
        axis = parse_grid_spec("iron_oxide=0.001:0.05:8")
        assert axis.name == "iron_oxide"
        np.testing.assert_allclose(axis.values, np.linspace(0.001, 0.05, 8))
        assert axis.values[0] == 0.001 and axis.values[-1] == 0.05

    def test_spaces_decreasing_and_single(self):
        axis = parse_grid_spec(" saturation = 1 : 0 : 3 ")
        np.testing.assert_allclose(axis.values, [1.0, 0.5, 0.0])
        np.testing.assert_allclose(parse_grid_spec("saturation=0.3:0.3:1").values, [0.3])

    @pytest.mark.parametrize(
        "text",
        [
            "iron_oxide",
            "iron_oxide=0:1",
            "iron_oxide=0:1:2:3",
            "=0:1:3",
            "2x=0:1:3",
            "iron_oxide=a:1:3",
            "iron_oxide=0:1:2.5",
            "iron_oxide=0:1:0",
            "iron_oxide=0:1:65",
            "iron_oxide=0:1:1",
            "iron_oxide=nan:1:3",
            "iron_oxide=0:inf:3",
        ],
    )
    def test_bad_specs_name_the_text(self, text):
        with pytest.raises(ParameterError) as info:
            parse_grid_spec(text)
        assert repr(text) in str(info.value)
        assert "grid spec" in str(info.value)


class TestSwatchGrid:
    def test_cells_in_row_major_order(self, fake_sample, fake_provider):
        x = ("iron_oxide", [0.001, 0.02, 0.05])
        y = ("hematite_ratio", [0.0, 1.0])
        grid = swatch_grid(fake_sample, x, y, reflectance=fake_provider)
        assert grid.rgb.shape == grid.lab.shape == grid.xyz.shape == (2, 3, 3)
        assert grid.out_of_gamut.shape == (2, 3)
        assert fake_provider.calls == 1
        for j, h in enumerate(y[1]):
            for i, c in enumerate(x[1]):
                expected = sample_rgb(fake_sample.replace(iron_oxide=c, hematite_ratio=h), reflectance=fake_provider)
                np.testing.assert_allclose(grid.rgb[j, i], expected, rtol=1e-14)

    def test_spec_strings_and_paper_mode(self, fake_sample, fake_provider):
        grid = swatch_grid(
            fake_sample, "saturation=0:1:4", "hematite_ratio=0:1:2", mode="paper", reflectance=fake_provider
        )
        assert grid.mode == "paper" and grid.rgb.shape == (2, 4, 3)

    def test_same_parameter_twice(self, fake_sample, fake_provider):
        with pytest.raises(ParameterError, match="other than x"):
            swatch_grid(fake_sample, "saturation=0:1:4", "saturation=0:1:2", reflectance=fake_provider)

    def test_base_without_replace(self, fake_provider):
        with pytest.raises(ParameterError, match="replace"):
            swatch_grid(object(), "saturation=0:1:4", "hematite_ratio=0:1:2", reflectance=fake_provider)

    def test_figure6_and_figure7_axes(self, fake_sample, fake_provider):
        f6 = figure6(fake_sample, reflectance=fake_provider)
        assert (f6.x.name, f6.y.name) == ("iron_oxide", "hematite_ratio")
        assert (f6.x.values[0], f6.x.values[-1]) == (0.001, 0.05)
        # hematite ratio increases downward: row 0 is 0
        assert (f6.y.values[0], f6.y.values[-1]) == (0.0, 1.0)
        f7 = figure7(fake_sample, n_x=3, n_y=2, reflectance=fake_provider)
        assert (f7.x.name, f7.y.name) == ("hematite_ratio", "saturation")
        assert f7.rgb.shape == (2, 3, 3)


class TestPng:
    def test_default_size_and_cell_colours(self, tmp_path, fake_sample, fake_provider):
        grid = swatch_grid(fake_sample, "iron_oxide=0.001:0.05:4", "hematite_ratio=0:1:3", reflectance=fake_provider)
        path = grid.save_png(tmp_path / "grid.png", title="test")
        with Image.open(path) as im:
            assert im.size == framed_size_px(4 * 96, 3 * 96)
            pixels = np.asarray(im.convert("RGB"))
        # The centre of cell (row 1, column 2) shows that cell's colour, to 8-bit rounding.
        left, top = 130, 50  # margins of the layout
        centre = pixels[top + 96 + 48, left + 2 * 96 + 48]
        np.testing.assert_allclose(centre, np.rint(grid.rgb[1, 2] * 255), atol=1)

    @pytest.mark.parametrize("show_lab", [False, True])
    def test_requested_size(self, tmp_path, fake_sample, fake_provider, show_lab):
        grid = swatch_grid(fake_sample, "iron_oxide=0.001:0.05:8", "hematite_ratio=0:1:6", reflectance=fake_provider)
        path = grid.save_png(tmp_path / "g.png", size_px=(640, 480), show_lab=show_lab)
        with Image.open(path) as im:
            assert im.size == (640, 480)

    def test_too_small_size(self, tmp_path, fake_sample, fake_provider):
        grid = swatch_grid(fake_sample, "iron_oxide=0.001:0.05:8", "hematite_ratio=0:1:6", reflectance=fake_provider)
        with pytest.raises(ParameterError, match="size_px"):
            grid.save_png(tmp_path / "g.png", size_px=(100, 100))
        assert not list(tmp_path.iterdir())

    def test_a_size_needing_too_much_memory_is_refused_before_drawing(self, tmp_path, fake_sample, fake_provider):
        grid = swatch_grid(fake_sample, "iron_oxide=0.001:0.05:8", "hematite_ratio=0:1:6", reflectance=fake_provider)
        with pytest.raises(ParameterError, match=r"size_px = \(20000, 20000\).*13.4 GiB of memory"):
            grid.save_png(tmp_path / "g.png", size_px=(20000, 20000))
        assert not list(tmp_path.iterdir())

    def test_missing_output_directory(self, tmp_path, fake_sample, fake_provider):
        grid = swatch_grid(fake_sample, "iron_oxide=0.001:0.05:2", "hematite_ratio=0:1:2", reflectance=fake_provider)
        with pytest.raises(FileNotFoundError, match="nowhere"):
            grid.save_png(tmp_path / "nowhere" / "g.png")


@pytest.fixture
def cli(monkeypatch, fake_provider):
    """The CLI with the fake provider as default and FakeSample as the sample class."""
    import sandlight.cli.colour as cli_colour
    import sandlight.colour.provider as provider

    monkeypatch.setattr(provider, "default_reflectance_provider", lambda: fake_provider)
    monkeypatch.setattr(cli_colour, "load_sample", lambda sample_file, preset, **kw: FakeSample(iron_oxide=0.03))
    return CliRunner()


class TestSwatchesCommand:
    def test_grid_of_requested_size(self, cli, tmp_path):
        out = tmp_path / "grid.png"
        result = cli.invoke(
            app,
            [
                "swatches",
                "--x",
                "iron_oxide=0.001:0.05:8",
                "--y",
                "hematite_ratio=0:1:6",
                "--size",
                "700x500",
                "--lab",
                "-o",
                str(out),
            ],
        )
        assert result.exit_code == 0, result.output
        with Image.open(out) as im:
            assert im.size == (700, 500)

    @pytest.mark.parametrize("figure, cells", [("6", (8, 6)), ("7", (6, 5))])
    def test_figures(self, cli, tmp_path, figure, cells):
        out = tmp_path / f"f{figure}.png"
        result = cli.invoke(app, ["swatches", "--figure", figure, "--mode", "paper", "-o", str(out)])
        assert result.exit_code == 0, result.output
        with Image.open(out) as im:
            assert im.size == framed_size_px(96 * cells[0], 96 * cells[1])

    @pytest.mark.parametrize(
        "args, message",
        [
            (["--x", "iron_oxide=0.001:0.05", "--y", "hematite_ratio=0:1:6"], "iron_oxide=0.001:0.05"),
            (["--x", "iron_oxide=0.001:0.05:8"], "--x and --y go together"),
            (["--figure", "6", "--x", "a=0:1:2", "--y", "b=0:1:2"], "not both"),
            (["--size", "big"], "--size 'big'"),
            (["--size", "20000x20000"], "needs about 13.4 GiB of memory, more than the limit of 2 GiB"),
            (["--mode", "cmyk"], "cmyk"),
            (["--figure", "8"], "8"),
        ],
    )
    def test_bad_input_exits_2_without_traceback(self, cli, tmp_path, args, message):
        result = cli.invoke(app, ["swatches", *args, "-o", str(tmp_path / "g.png")])
        assert result.exit_code == 2
        assert message in result.output
        assert "Traceback" not in result.output
        assert not (tmp_path / "g.png").exists()

    def test_not_png(self, cli, tmp_path):
        result = cli.invoke(app, ["swatches", "-o", str(tmp_path / "g.jpg")])
        assert result.exit_code == 2 and ".png" in result.output

    def test_no_model_exits_1_with_message(self, tmp_path, monkeypatch):
        import sys

        import sandlight.cli.colour as cli_colour

        monkeypatch.setitem(sys.modules, "sandlight.predictor", None)
        monkeypatch.setattr(cli_colour, "load_sample", lambda sample_file, preset, **kw: FakeSample())
        result = CliRunner().invoke(app, ["swatches", "-o", str(tmp_path / "g.png")])
        assert result.exit_code == 1
        assert "No spectral model is available" in result.output
        assert "Traceback" not in result.output


class TestSwatchesWithTheEngine:
    def test_engine_grid_of_real_samples(self, tmp_path):
        out = tmp_path / "engine.png"
        result = CliRunner().invoke(
            app,
            [
                "swatches",
                "--x",
                "iron_oxide=0.001:0.02:2",
                "--y",
                "saturation=0:0:1",
                "--engine-rays",
                "200",
                "--size",
                "300x200",
                "-o",
                str(out),
            ],
        )
        assert result.exit_code == 0, result.output
        with Image.open(out) as im:
            assert im.size == (300, 200)

    def test_engine_rays_must_be_positive(self, tmp_path):
        result = CliRunner().invoke(app, ["swatches", "--engine-rays", "0", "-o", str(tmp_path / "g.png")])
        assert result.exit_code == 2
        assert "--engine-rays = '0' is not allowed" in result.output and "Traceback" not in result.output
