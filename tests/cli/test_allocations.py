"""Sizes inside every parameter's own range that multiply to more memory than allowed are refused
before anything is allocated, with the estimate and the limit (issue 24 #5): exit 2, one message
naming the option, no file written."""

import pytest
from PIL import Image
from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()

LIMIT = "more than the limit of 2 GiB"


def _refused(args, message, out):
    res = runner.invoke(app, args)
    assert res.exit_code == 2, res.output
    assert message in res.output and LIMIT in res.output and "Traceback" not in res.output, res.output
    assert not out.exists()


def test_render_refuses_a_frame_larger_than_the_limit(tmp_path):
    # 16384² at 16 bands: about 40 GiB of frame arrays
    args = ["render", "desert-day", "-o", str(tmp_path / "frames"), "--width", "16384", "--height", "16384"]
    _refused(args, "width × height = '16384×16384 pixels' is not allowed: needs about 39.8 GiB", tmp_path / "frames")


def test_appearance_refuses_a_table_larger_than_the_limit(tmp_path):
    args = ["appearance", "--preset", "red-dune", "--table", str(tmp_path / "t.nc"), "--n-mu", "4096"]
    message = "--n-mu, --n-dphi = (4096, 4096) is not allowed: needs about"
    _refused([*args, "--n-dphi", "4096"], message, tmp_path / "t.nc")


def test_sky_refuses_a_strip_of_a_thousand_domes(tmp_path):
    times = ",".join(["12"] * 1000)
    args = ["sky", "--latitude", "30", "--day", "100", "--times", times, "-o", str(tmp_path / "s.png")]
    _refused(args, "--times = '1000 domes of 512² pixels' is not allowed: needs about 19.5 GiB", tmp_path / "s.png")


def test_colourise_refuses_a_mosaic_larger_than_the_limit(tmp_path):
    args = ["colourise", "--grid", "--x", "iron_oxide=0.001:0.05:8", "--y", "hematite_ratio=0:1:6"]
    _refused(
        [*args, "--tile", "4096x4096", "-o", str(tmp_path / "g.png")],
        "--tile = '8×6 tiles of 4096×4096 pixels' is not allowed: needs about 45.1 GiB",
        tmp_path / "g.png",
    )


def test_colourise_refuses_a_photo_too_large_before_decoding_it(tmp_path):
    photo = tmp_path / "big.png"
    Image.new("RGB", (12000, 12000)).save(photo)  # all black: a small file, 144 million pixels
    args = ["colourise", str(photo), "--preset", "red-dune", "-o", str(tmp_path / "c.png")]
    _refused(args, "(12000×12000 pixels)' is not allowed: needs about 14.8 GiB", tmp_path / "c.png")


@pytest.mark.parametrize("command", ["colourise", "render"])
def test_a_decompression_bomb_is_a_message_not_a_traceback(tmp_path, command):
    # 30000² pixels: pillow raises DecompressionBombError (was uncaught for heightfields)
    bomb = tmp_path / "bomb.png"
    Image.new("L", (30000, 30000)).save(bomb)
    if command == "colourise":
        args = ["colourise", str(bomb), "--preset", "red-dune", "-o", str(tmp_path / "c.png")]
    else:
        scene = tmp_path / "hf.toml"
        scene.write_text(
            "[sun]\nlatitude_deg = 25.0\nday_of_year = 110\nstart_h = 12.0\nend_h = 12.0\n"
            '[terrain]\ntype = "image"\npath = "bomb.png"\nheight_range_m = [0.0, 5.0]\nsize_m = [100.0, 100.0]\n'
        )
        args = ["render", str(scene), "-o", str(tmp_path / "frames"), "--width", "32", "--height", "18"]
    res = runner.invoke(app, args)
    assert res.exit_code == 2 and "Traceback" not in res.output, res.output
    assert f"= '{bomb}' is not allowed: an image of at most" in res.output, res.output
    assert "decompression bomb" in res.output
