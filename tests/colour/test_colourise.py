"""Colourisation (§4.1.1), image I/O, the shipped texture, the colourise command."""

import numpy as np
import pytest
from colour_fakes import FakeSample
from PIL import Image
from typer.testing import CliRunner

import colour
from sandlight.cli import app
from sandlight.colour import (
    colourise,
    colourise_grid,
    default_texture_path,
    load_image,
    sample_rgb,
    save_image,
)
from sandlight.colour.swatches import framed_size_px
from sandlight.errors import ParameterError, SandlightError


@pytest.fixture
def photo():
    """A small image with values well inside (0, 1) so that shifts do not clip."""
    rng = np.random.default_rng(11)
    return rng.uniform(0.35, 0.65, (24, 32, 3))


class TestColourise:
    def test_paper_recipe(self, photo):
        target = np.array([0.6, 0.4, 0.25])
        out = colourise(photo, target)
        # §4.1.1: subtract the image's mean RGB, add the sample's RGB, per pixel.
        np.testing.assert_allclose(out, photo - photo.mean(axis=(0, 1)) + target, rtol=1e-14)
        np.testing.assert_allclose(out.mean(axis=(0, 1)), target, rtol=1e-12)
        assert out.shape == photo.shape

    def test_clipping(self, photo):
        out = colourise(photo, [0.95, 0.05, 0.5])
        assert out.min() >= 0.0 and out.max() <= 1.0
        assert np.any(out[..., 0] == 1.0) and np.any(out[..., 1] == 0.0)

    def test_linear_option_shifts_in_linear_light(self, photo):
        target = np.array([0.7, 0.6, 0.55])  # linear ≥ 0.26: no channel clips
        out = colourise(photo, target, linear=True)
        out_lin = colour.models.eotf_sRGB(out)
        np.testing.assert_allclose(out_lin.mean(axis=(0, 1)), colour.models.eotf_sRGB(target), rtol=1e-10)
        assert np.max(np.abs(out - colourise(photo, target))) > 1e-3

    def test_sample_uses_its_srgb(self, photo, fake_sample, fake_provider):
        for mode in ("managed", "paper"):
            rgb = sample_rgb(fake_sample, mode=mode, reflectance=fake_provider)
            expected = colourise(photo, rgb)
            np.testing.assert_allclose(colourise(photo, fake_sample, mode=mode, reflectance=fake_provider), expected)

    def test_uint8_image(self, photo):
        img8 = np.rint(photo * 255).astype(np.uint8)
        np.testing.assert_allclose(
            colourise(img8, [0.5, 0.4, 0.3]), colourise(img8 / 255.0, [0.5, 0.4, 0.3]), rtol=1e-14
        )

    @pytest.mark.parametrize("image", [np.zeros((4, 4)), np.full((4, 4, 3), 1.5), np.full((4, 4, 3), np.nan)])
    def test_bad_image_array(self, image):
        with pytest.raises(ParameterError, match="image"):
            colourise(image, [0.5, 0.4, 0.3])

    @pytest.mark.parametrize("rgb", [[0.5, 0.4], [0.5, 0.4, 1.2]])
    def test_bad_rgb(self, photo, rgb):
        with pytest.raises(ParameterError, match="sample_or_rgb"):
            colourise(photo, rgb)


class TestColouriseGrid:
    def test_mosaic_layout(self, photo, fake_sample, fake_provider):
        result = colourise_grid(
            photo, fake_sample, "iron_oxide=0.001:0.05:3", "hematite_ratio=0:1:2", gap_px=5, reflectance=fake_provider
        )
        h, w = photo.shape[:2]
        assert result.mosaic.shape == (2 * h + 5, 3 * w + 2 * 5, 3)
        assert fake_provider.calls == 1
        # Tile (row 1, column 2) is the photo colourised with that cell's sample.
        tile = result.mosaic[h + 5 : 2 * h + 5, 2 * (w + 5) : 2 * (w + 5) + w]
        sample = fake_sample.replace(iron_oxide=0.05, hematite_ratio=1.0)
        np.testing.assert_allclose(tile, colourise(photo, sample, reflectance=fake_provider))
        np.testing.assert_array_equal(result.mosaic[h : h + 5], 1.0)  # white gap

    def test_tile_size(self, photo, fake_sample, fake_provider):
        result = colourise_grid(
            photo,
            fake_sample,
            "saturation=0:1:2",
            "hematite_ratio=0:1:2",
            tile_px=(40, 30),
            gap_px=0,
            reflectance=fake_provider,
        )
        assert result.mosaic.shape == (60, 80, 3)

    def test_bad_gap(self, photo, fake_sample, fake_provider):
        with pytest.raises(ParameterError, match="gap_px"):
            colourise_grid(
                photo, fake_sample, "saturation=0:1:2", "hematite_ratio=0:1:2", gap_px=-1, reflectance=fake_provider
            )

    def test_png_with_and_without_labels(self, tmp_path, photo, fake_sample, fake_provider):
        result = colourise_grid(
            photo, fake_sample, "saturation=0:1:2", "hematite_ratio=0:1:3", gap_px=2, reflectance=fake_provider
        )
        bare = result.save_png(tmp_path / "bare.png", labels=False)
        framed = result.save_png(tmp_path / "framed.png")
        with Image.open(bare) as im:
            assert im.size == (2 * 32 + 2, 3 * 24 + 2 * 2)
        with Image.open(framed) as im:
            assert im.size == framed_size_px(2 * 32 + 2, 3 * 24 + 2 * 2)


class TestImageIO:
    def test_shipped_texture(self):
        img = load_image(default_texture_path())
        assert img.shape == (256, 256, 3)
        assert img.min() >= 0.0 and img.max() <= 1.0
        assert 0.2 < img.mean() < 0.8 and img.std() > 0.05  # a textured, mid-tone image

    def test_round_trip(self, tmp_path, photo):
        path = save_image(tmp_path / "p.png", photo)
        np.testing.assert_allclose(load_image(path), np.rint(photo * 255) / 255, atol=1e-12)

    def test_greyscale_and_16_bit(self, tmp_path):
        Image.fromarray(np.full((5, 6), 128, np.uint8)).save(tmp_path / "g.png")
        Image.fromarray(np.full((5, 6), 65535 // 4, np.uint16)).save(tmp_path / "g16.png")
        np.testing.assert_allclose(load_image(tmp_path / "g.png"), 128 / 255)
        np.testing.assert_allclose(load_image(tmp_path / "g16.png"), (65535 // 4) / 65535)

    def test_missing_path(self, tmp_path):
        missing = tmp_path / "no-such-photo.jpg"
        with pytest.raises(FileNotFoundError, match="no-such-photo.jpg"):
            load_image(missing)

    @pytest.mark.parametrize("content", [b"this is not an image\n", None], ids=["text", "truncated"])
    def test_unreadable_image(self, tmp_path, content):
        path = tmp_path / "broken.png"
        if content is None:  # the first half of a real PNG
            data = default_texture_path().read_bytes()
            content = data[: len(data) // 2]
        path.write_bytes(content)
        with pytest.raises(SandlightError, match="broken.png"):
            load_image(path)

    def test_directory_is_not_an_image(self, tmp_path):
        with pytest.raises(SandlightError, match="not a regular file"):
            load_image(tmp_path)

    def test_unknown_output_extension(self, tmp_path, photo):
        with pytest.raises(ParameterError, match="out.xyz"):
            save_image(tmp_path / "out.xyz", photo)


@pytest.fixture
def cli(monkeypatch, fake_provider):
    """The CLI with the fake provider as default and FakeSample as the sample class."""
    import sandlight.cli.colour as cli_colour
    import sandlight.colour.provider as provider

    monkeypatch.setattr(provider, "default_reflectance_provider", lambda: fake_provider)
    monkeypatch.setattr(cli_colour, "load_sample", lambda sample_file, preset, **kw: FakeSample(iron_oxide=0.03))
    return CliRunner()


class TestColouriseCommand:
    def test_default_texture(self, cli, tmp_path):
        out = tmp_path / "out.png"
        result = cli.invoke(app, ["colourise", "--preset", "red-dune", "-o", str(out)])
        assert result.exit_code == 0, result.output
        with Image.open(out) as im:
            assert im.size == (256, 256)

    def test_given_image_keeps_its_size(self, cli, tmp_path, photo):
        src = save_image(tmp_path / "photo.jpg", photo)
        out = tmp_path / "out.jpg"
        result = cli.invoke(app, ["colourise", str(src), "--preset", "red-dune", "--linear", "-o", str(out)])
        assert result.exit_code == 0, result.output
        with Image.open(out) as im:
            assert im.size == (32, 24)

    def test_grid(self, cli, tmp_path):
        out = tmp_path / "grid.png"
        result = cli.invoke(
            app,
            [
                "colourise",
                "--grid",
                "--x",
                "hematite_ratio=0:1:3",
                "--y",
                "saturation=0:1:2",
                "--tile",
                "64x48",
                "--no-labels",
                "-o",
                str(out),
            ],
        )
        assert result.exit_code == 0, result.output
        with Image.open(out) as im:
            assert im.size == (3 * 64 + 2 * 4, 2 * 48 + 4)

    @pytest.mark.parametrize(
        "args, message",
        [
            (["missing.jpg", "--preset", "red-dune"], "missing.jpg"),
            (["--grid", "--x", "hematite_ratio=0:1", "--y", "saturation=0:1:2"], "hematite_ratio=0:1"),
            (["--grid", "--x", "hematite_ratio=0:1:3"], "--grid needs"),
            ([], "--preset NAME or --sample FILE"),
            (["--preset", "red-dune", "--x", "hematite_ratio=0:1:3"], "need --grid"),
            (["--grid", "--x", "a=0:1:2", "--y", "b=0:1:2", "--tile", "0x"], "--tile '0x'"),
        ],
    )
    def test_bad_input_exits_2(self, cli, tmp_path, args, message):
        result = cli.invoke(app, ["colourise", *args, "-o", str(tmp_path / "out.png")])
        assert result.exit_code == 2
        assert message in result.output
        assert "Traceback" not in result.output
        assert not (tmp_path / "out.png").exists()

    def test_unreadable_image_exits_2(self, cli, tmp_path):
        bad = tmp_path / "bad.jpg"
        bad.write_text("not a jpeg")
        result = cli.invoke(app, ["colourise", str(bad), "--preset", "red-dune", "-o", str(tmp_path / "out.png")])
        assert result.exit_code == 2
        assert "bad.jpg" in result.output and "Traceback" not in result.output
