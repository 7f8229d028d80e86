"""Fisheye pictures of the sky and the ``sandlight sky`` command."""

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.errors import ParameterError
from sandlight.sky import PreethamSky, direction_from_angles
from sandlight.sky.plots import fisheye_directions, plot_sky_day, plot_sky_dome, sky_dome_xyz, xyz_to_display_srgb


def sky_with_sun_at(elevation_deg, azimuth_deg, turbidity=3.0):
    return PreethamSky(turbidity, direction_from_angles(np.radians(90.0 - elevation_deg), np.radians(azimuth_deg)))


class TestFisheye:
    def test_equidistant_looking_up_orientation(self):
        size = 65
        directions, inside = fisheye_directions(size)
        centre = directions[size // 2, size // 2]
        np.testing.assert_allclose(centre, [0.0, 0.0, 1.0], atol=1e-12)
        # Half-way to the rim is 45° from the zenith (equidistant).
        half = directions[size // 2, size // 2 - size // 4]
        assert np.degrees(np.arccos(half[2])) == pytest.approx(45.0, abs=2.0)
        # Top of the image is north, left is east (seen from below).
        assert directions[1, size // 2][1] > 0.99
        assert directions[size // 2, 1][0] > 0.99
        assert not inside[0, 0] and inside[size // 2, size // 2]

    def test_dome_luminance_and_sun_side(self):
        sky = sky_with_sun_at(25.0, 90.0)  # low morning sun in the east
        xyz, inside = sky_dome_xyz(sky, 33)
        # Centre pixel: the zenith, Y in cd/m² equals the model's Y_z (kcd/m²) within the
        # 5 nm integration error.
        assert xyz[16, 16, 1] == pytest.approx(1000.0 * sky.zenith_luminance_kcd_m2, rel=5e-3)
        luminance = np.where(inside, xyz[..., 1], 0.0)
        row, column = np.unravel_index(np.argmax(luminance), luminance.shape)
        assert column < 16  # the brightest sky is on the left, i.e. east

    def test_display_srgb_blue_zenith_and_range(self):
        sky = sky_with_sun_at(60.0, 180.0, turbidity=2.5)
        xyz, inside = sky_dome_xyz(sky, 17)
        rgb = xyz_to_display_srgb(xyz, 2.0 * xyz[8, 8, 1])
        assert rgb.min() >= 0.0 and rgb.max() <= 1.0
        red, green, blue = rgb[8, 8]
        assert blue > red
        with pytest.raises(ParameterError):
            xyz_to_display_srgb(xyz, 0.0)

    def test_plot_sky_dome_writes_png(self, tmp_path):
        path = plot_sky_dome(sky_with_sun_at(40.0, 150.0), tmp_path / "sub" / "dome.png", size=64)
        with Image.open(path) as image:
            assert image.format == "PNG" and image.size[0] >= 64
        assert [p.name for p in path.parent.iterdir()] == ["dome.png"]  # no temporary left

    def test_plot_sky_day_handles_night_panels(self, tmp_path):
        path = plot_sky_day(30.0, 172, [3.0, 9.0, 12.0], tmp_path / "day.png", size=32)
        with Image.open(path) as image:
            assert image.format == "PNG"

    @pytest.mark.parametrize(
        "kwargs, name",
        [
            (dict(size=8), "size"),
            (dict(size=64.5), "size"),
            (dict(turbidity=0.5), "turbidity"),
            (dict(times_h=[9.0, 25.0]), "times_h"),
            (dict(latitude_deg=-100.0), "latitude_deg"),
        ],
    )
    def test_plot_sky_day_rejects_bad_values(self, tmp_path, kwargs, name):
        arguments = dict(latitude_deg=30.0, day_of_year=172, times_h=[9.0, 12.0], path=tmp_path / "x.png", size=32)
        arguments.update(kwargs)
        with pytest.raises(ParameterError) as info:
            plot_sky_day(**arguments)
        assert info.value.name == name
        assert not (tmp_path / "x.png").exists()


class TestCommand:
    def test_one_dome(self, tmp_path):
        out = tmp_path / "sky.png"
        result = CliRunner().invoke(
            app,
            [
                "sky",
                "--latitude",
                "30",
                "--day",
                "172",
                "--time",
                "10.5",
                "--turbidity",
                "3",
                "--size",
                "48",
                "-o",
                str(out),
            ],
        )
        assert result.exit_code == 0, result.output
        assert "sun elevation 68.9" in result.output
        assert out.exists()

    def test_strip_with_clock_time(self, tmp_path):
        out = tmp_path / "day.png"
        result = CliRunner().invoke(
            app,
            [
                "sky",
                "--latitude",
                "33.45",
                "--longitude",
                "-112.07",
                "--utc-offset",
                "-7",
                "--day",
                "80",
                "--times",
                "7,12,17",
                "--size",
                "24",
                "-o",
                str(out),
            ],
        )
        assert result.exit_code == 0, result.output
        assert out.exists()

    @pytest.mark.parametrize(
        "arguments, fragment",
        [
            (["--latitude", "95", "--day", "172", "--time", "10"], "--latitude"),
            (["--latitude", "30", "--day", "0", "--time", "10"], "--day"),
            (["--latitude", "30", "--day", "172", "--time", "10", "--turbidity", "20"], "--turbidity"),
            (["--latitude", "30", "--day", "172", "--time", "23"], "below the horizon"),
            (["--latitude", "30", "--day", "172"], "--time"),
            (["--latitude", "30", "--day", "172", "--time", "10", "--longitude", "5"], "--utc-offset"),
        ],
    )
    def test_bad_values_give_clear_errors(self, tmp_path, arguments, fragment):
        out = tmp_path / "sky.png"
        result = CliRunner().invoke(app, ["sky", *arguments, "-o", str(out)])
        assert result.exit_code == 2
        assert fragment in " ".join(result.output.split())
        assert not out.exists()
