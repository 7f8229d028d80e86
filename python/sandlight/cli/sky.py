"""Command of the daylight area: ``sandlight sky`` draws the Preetham sky for a place and time."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from sandlight.cli._app import app
from sandlight.cli._common import option_names
from sandlight.cli._output import echo
from sandlight.errors import ParameterError
from sandlight.io import check_output_file

#: The parameters of the sky functions as this command's options, for messages.
_OPTIONS = {
    "latitude_deg": "--latitude",
    "day_of_year": "--day",
    "time_h": "--time",
    "standard_time_h": "--time",
    "times_h": "--times",
    "turbidity": "--turbidity",
    "longitude_deg": "--longitude",
    "utc_offset_h": "--utc-offset",
    "size": "--size",
    "exposure_cd_m2": "--exposure",
}


def _parse_times(text: str) -> list[float]:
    try:
        return [float(item) for item in text.split(",") if item.strip()]
    except ValueError:
        raise ParameterError("--times", text, "a comma-separated list of hours, e.g. 6,8,10,12") from None


@app.command()
def sky(
    latitude: float = typer.Option(..., help="Latitude in degrees, north positive, [-90, 90]."),
    day: int = typer.Option(..., help="Day of the year, 1 (1 January) to 366."),
    time: float | None = typer.Option(
        None,
        help="Time of day in hours [0, 24]: solar time, or clock time if --longitude and "
        "--utc-offset are given. Draws one dome.",
    ),
    times: str | None = typer.Option(
        None,
        help="Comma-separated times of day (e.g. 6,8,10,12,14,16,18): draws a strip of "
        "domes over the day instead of one.",
    ),
    turbidity: float = typer.Option(3.0, help="Turbidity T in [1.7, 10] (2 very clear, 3 clear, 6 moist, 10 hazy)."),
    longitude: float | None = typer.Option(
        None, help="Longitude in degrees, east positive, [-180, 180]; with --utc-offset."
    ),
    utc_offset: float | None = typer.Option(
        None, help="Time-zone offset from UTC in hours, [-12, 14]; with --longitude."
    ),
    size: int = typer.Option(512, help="Dome diameter in pixels [16, 4096] (per dome)."),
    exposure: float | None = typer.Option(
        None, help="Luminance shown as white, kcd/m^2 (default: twice the median sky luminance)."
    ),
    output: Path = typer.Option(..., "--output", "-o", help="Output PNG file (.png, overwritten if it exists)."),
) -> None:
    """Draw the Preetham et al. (1999) clear sky as an equidistant fisheye PNG (looking up:
    north at the top, east on the left), the sun marked."""
    from sandlight.sky import PreethamSky, sun_position
    from sandlight.sky.plots import plot_sky_day, plot_sky_dome

    check_output_file(output, "--output", (".png",), make_dirs=True)
    if (time is None) == (times is None):
        raise ParameterError("--time/--times", "both" if time is not None else "neither", "exactly one of them")
    exposure_cd_m2 = None if exposure is None else exposure * 1000.0
    if exposure is not None and not exposure > 0.0:
        raise ParameterError("--exposure", exposure, "a luminance > 0 in kcd/m^2")
    with option_names(_OPTIONS):
        if time is not None:
            zenith, azimuth = sun_position(latitude, day, time, longitude_deg=longitude, utc_offset_h=utc_offset)
            elevation = 90.0 - math.degrees(float(zenith))
            if elevation <= 0.0:
                raise ParameterError(
                    "--time",
                    time,
                    f"a daytime hour: the sun is {-elevation:.1f}° below the horizon at {time} h on day {day} "
                    f"at latitude {latitude}°",
                )
            model = PreethamSky.from_location(
                turbidity, latitude, day, time, longitude_deg=longitude, utc_offset_h=utc_offset
            )
            path = plot_sky_dome(model, output, size=size, exposure_cd_m2=exposure_cd_m2)
            echo(
                f"sun elevation {elevation:.2f}°, azimuth "
                f"{math.degrees(float(azimuth)):.2f}° (from north, "
                f"clockwise); zenith luminance {model.zenith_luminance_kcd_m2:.3f} kcd/m²"
            )
        else:
            path = plot_sky_day(
                latitude,
                day,
                _parse_times(times),
                output,
                turbidity=turbidity,
                longitude_deg=longitude,
                utc_offset_h=utc_offset,
                size=size,
                exposure_cd_m2=exposure_cd_m2,
            )
    echo(f"wrote {path}")
