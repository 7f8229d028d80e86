#!/usr/bin/env python3
"""Cross-checks of sandlight's daylight model; prints the figures quoted in docs/daylight.md.

Usage::

    PYTHONPATH=python python3 scripts/studies/check_sky.py [--figures DIR]

Checks:
1. Sun position (Preetham appendix) against NOAA/Spencer and against pvlib's NREL SPA.
2. Direct-beam sun spectrum (Preetham/Iqbal transmittances) against pvlib's SPECTRL2, the effect
   of the relative optical mass as printed in the paper, and the extraterrestrial spectrum against
   the authors' table.
3. Sky: zenith values, spectral reconstruction of (Y, x, y) with and without M1/M2 rounding,
   diffuse horizontal illuminance against SPECTRL2, and evaluation speed.
With ``--figures DIR`` also writes a one-dome and a day-strip picture there.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import numpy.typing as npt

from sandlight.sky import PreethamSky, direction_from_angles, solar_declination, solar_time, sun_direction, sun_position
from sandlight.sky import sun_spectrum as ss
from sandlight.sky.preetham import daylight_basis, daylight_m1_m2

VISIBLE_NM = np.arange(380.0, 781.0, 5.0)


def cmfs(wavelength_nm: npt.ArrayLike) -> np.ndarray:
    import colour

    table = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.stack([np.interp(wavelength_nm, table.wavelengths, table.values[:, i]) for i in range(3)], axis=-1)


def illuminance_lx(
    spectral_irradiance: np.ndarray, wavelength_nm: np.ndarray = VISIBLE_NM, step_nm: float = 5.0
) -> np.ndarray:
    return 683.0 * spectral_irradiance @ cmfs(wavelength_nm)[:, 1] * step_nm


def spencer_declination(day: np.ndarray) -> np.ndarray:
    g = 2.0 * np.pi / 365.0 * (day - 1.0)
    return (
        0.006918
        - 0.399912 * np.cos(g)
        + 0.070257 * np.sin(g)
        - 0.006758 * np.cos(2 * g)
        + 0.000907 * np.sin(2 * g)
        - 0.002697 * np.cos(3 * g)
        + 0.00148 * np.sin(3 * g)
    )


def spencer_equation_of_time_min(day: np.ndarray) -> np.ndarray:
    g = 2.0 * np.pi / 365.0 * (day - 1.0)
    return 229.18 * (
        0.000075 + 0.001868 * np.cos(g) - 0.032077 * np.sin(g) - 0.014615 * np.cos(2 * g) - 0.040849 * np.sin(2 * g)
    )


def separation_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)))


def check_sun_position() -> None:
    print("== 1. Sun position (Preetham appendix)")
    day = np.arange(1.0, 366.0)
    decl_err = np.degrees(solar_declination(day) - spencer_declination(day))
    eot_err = (solar_time(12.0, day, 0.0, 0.0) - 12.0) * 60.0 - spencer_equation_of_time_min(day)
    print(
        f"declination vs Spencer: max |err| {np.abs(decl_err).max():.2f} deg "
        f"(day {int(day[np.abs(decl_err).argmax()])}), mean {np.abs(decl_err).mean():.2f} deg"
    )
    print(f"equation of time vs Spencer: max |err| {np.abs(eot_err).max():.2f} min")

    # NOAA/Spencer direction over latitudes x days x solar times.
    lat = np.array([-60.0, -35.0, 0.0, 23.4, 30.0, 52.0, 70.0])[:, None, None]
    d = day[None, :, None]
    t = np.arange(0.0, 24.01, 0.25)[None, None, :]
    g = 2.0 * np.pi / 365.0 * (d - 1.0 + (t - 12.0) / 24.0)
    decl = spencer_declination(1.0 + g * 365.0 / (2 * np.pi))
    h = np.radians(15.0 * (t - 12.0))
    la = np.radians(lat)
    ref = np.stack(
        np.broadcast_arrays(
            -np.cos(decl) * np.sin(h),
            np.cos(la) * np.sin(decl) - np.sin(la) * np.cos(decl) * np.cos(h),
            np.sin(la) * np.sin(decl) + np.cos(la) * np.cos(decl) * np.cos(h),
        ),
        axis=-1,
    )
    sep = separation_deg(sun_direction(lat, d, t), ref)
    print(
        f"direction vs NOAA/Spencer ({sep.size} cases, 7 latitudes, every day, every 15 min): "
        f"max {sep.max():.2f} deg, mean {sep.mean():.2f} deg"
    )

    # The azimuth denominator as reproduced from the printed appendix (sign of cos l sin δ).
    delta = solar_declination(d)
    hour = np.pi * t / 12.0
    printed = np.mod(
        np.arctan2(
            -np.cos(delta) * np.sin(hour), np.cos(la) * np.sin(delta) - np.sin(la) * np.cos(delta) * np.cos(hour)
        )
        + np.pi,
        2 * np.pi,
    )
    zenith, azimuth = sun_position(lat, d, t)
    up = zenith < np.radians(85.0)
    wrong = np.degrees(np.abs(np.angle(np.exp(1j * (printed - azimuth)))))[np.broadcast_to(up, zenith.shape)]
    print(
        f"azimuth with the printed denominator (cos l sin d - ...) differs from the authors' code "
        f"by up to {wrong.max():.1f} deg (mean {wrong.mean():.1f} deg) for the sun above 5 deg"
    )

    try:
        import pandas as pd
        import pvlib
    except ImportError:
        print("pvlib not installed: SPA comparison skipped")
        return
    places = [("Phoenix", 33.45, -112.07, -7), ("Dunhuang", 40.14, 94.66, 8), ("Namib (Sossusvlei)", -24.73, 15.29, 2)]
    for name, lat_deg, lon_deg, offset in places:
        local = pd.date_range("2023-01-01", "2023-12-31 23:00", freq="37min")
        utc = local - pd.Timedelta(hours=offset)
        spa = pvlib.solarposition.get_solarposition(utc.tz_localize("UTC"), lat_deg, lon_deg, method="nrel_numpy")
        clock = np.asarray(local.hour + local.minute / 60.0, dtype=float)
        doy = np.asarray(local.day_of_year, dtype=float)
        ours = sun_direction(lat_deg, doy, clock, longitude_deg=lon_deg, utc_offset_h=offset)
        ref = direction_from_angles(np.radians(spa["zenith"].to_numpy()), np.radians(spa["azimuth"].to_numpy()))
        day_mask = ref[:, 2] > 0.0
        sep = separation_deg(ours, ref)[day_mask]
        print(
            f"vs pvlib SPA (true zenith), {name} 2023, clock time every 37 min, sun up: "
            f"max {sep.max():.2f} deg, mean {sep.mean():.2f} deg"
        )


def check_sun_spectrum() -> None:
    print("\n== 2. Direct-beam sun spectrum, T = 3, ozone 0.35 cm, water 2 cm")
    wl = np.array([400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0, 760.0, 800.0])
    print("ratio Preetham-1999 / Bird-Riordan-1986 (SPECTRL2), by wavelength (nm):")
    print("zenith  " + " ".join(f"{w:6.0f}" for w in wl) + "   E_v ratio  E_v(ours) klx")
    for zenith_deg in (0.0, 30.0, 60.0, 75.0, 85.0):
        z = np.radians(zenith_deg)
        ours = ss.sun_spectral_irradiance(z, wl, 3.0)
        theirs = ss.sun_spectral_irradiance(z, wl, 3.0, method="Bird-Riordan 1986")
        ev = illuminance_lx(ss.sun_spectral_irradiance(z, VISIBLE_NM, 3.0))
        ev_ref = illuminance_lx(ss.sun_spectral_irradiance(z, VISIBLE_NM, 3.0, method="Bird-Riordan 1986"))
        print(
            f"{zenith_deg:5.0f}   "
            + " ".join(f"{r:6.3f}" for r in ours / theirs)
            + f"   {ev / ev_ref:8.3f}  {ev / 1000:10.1f}"
        )

    print(
        "m as printed (inside the exponent of lambda) vs as coded (factor of the depth), "
        "Rayleigh x aerosol transmittance at 450 / 650 nm:"
    )
    for zenith_deg in (0.0, 45.0, 60.0, 75.0):
        z = np.radians(zenith_deg)
        m = ss.relative_optical_mass(z)
        lam = np.array([0.45, 0.65])
        beta = ss.angstrom_beta(3.0)
        coded = np.exp(-m * 0.008735 * lam**-4.08) * np.exp(-m * beta * lam**-1.3)
        printed = np.exp(-0.008735 * lam ** (-4.08 * m)) * np.exp(-beta * lam ** (-1.3 * m))
        print(
            f"  zenith {zenith_deg:4.0f} (m = {m:5.2f}): coded {coded[0]:.3f} / {coded[1]:.3f}, "
            f"printed {printed[0]:.3g} / {printed[1]:.3g}"
        )

    # Extraterrestrial solar spectral radiance of the authors' code (solAmplitudes, 380–750 nm in
    # 10 nm steps; values at six wavelengths), W m⁻² sr⁻¹ nm⁻¹, against SPECTRL2 / Ω.
    authors = {400.0: 21127.5, 450.0: 29658.3, 500.0: 28712.1, 550.0: 25503.8, 600.0: 24631.5, 650.0: 22339.8}
    lam = np.array(list(authors))
    ours = ss.extraterrestrial_spectral_irradiance(lam) / ss.SUN_SOLID_ANGLE_SR
    print(
        "extraterrestrial radiance, ours (SPECTRL2/Omega) / authors' table: "
        + ", ".join(f"{w:.0f} nm {o / a:.3f}" for w, o, a in zip(lam, ours, authors.values()))
    )

    # ASTM G173-03 (SMARTS2): extraterrestrial and direct+circumsolar spectra at air mass 1.5
    # (zenith 48.19°), rural aerosol with τ(500 nm) = 0.084, w = 1.42 cm, ozone 0.34 cm.
    import pvlib

    g173 = pvlib.spectrum.get_reference_spectra(standard="ASTM G173-03")
    grid = g173.index.to_numpy(dtype=float)

    def band_mean(column: str, centre: float):  # 10 nm means: SPECTRL2's grid does not resolve lines
        mask = (grid >= centre - 5.0) & (grid <= centre + 5.0)
        return np.trapezoid(g173[column].to_numpy()[mask], grid[mask]) / 10.0

    lam = np.array([400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0])
    et = np.array([band_mean("extraterrestrial", c) for c in lam])
    print(
        "extraterrestrial, ours / ASTM G173 (10 nm means): "
        + ", ".join(f"{w:.0f} {r:.3f}" for w, r in zip(lam, ss.extraterrestrial_spectral_irradiance(lam) / et))
    )
    turbidity = (0.084 / 0.5**-1.3 + 0.04586025928522) / 0.04608365822050
    direct = np.array([band_mean("direct", c) for c in lam])
    ours = ss.sun_spectral_irradiance(np.radians(48.19), lam, turbidity, ozone_cm=0.34, water_vapour_cm=1.42)
    fine = np.arange(380.0, 781.0, 1.0)
    ev_ours = illuminance_lx(
        ss.sun_spectral_irradiance(np.radians(48.19), fine, turbidity, ozone_cm=0.34, water_vapour_cm=1.42), fine, 1.0
    )
    ev_g173 = illuminance_lx(np.interp(fine, grid, g173["direct"].to_numpy()), fine, 1.0)
    print(
        f"direct beam at AM1.5 (T = {turbidity:.3f} gives tau500 = 0.084), ours / ASTM G173: "
        + ", ".join(f"{w:.0f} {r:.3f}" for w, r in zip(lam, ours / direct))
        + f"; illuminance {ev_ours / 1000:.1f} vs {ev_g173 / 1000:.1f} klx"
    )


def check_sky() -> None:
    print("\n== 3. Preetham sky")
    print("zenith luminance Y_z (kcd/m^2) and chromaticity (x_z, y_z):")
    for turbidity in (2.0, 3.0, 6.0):
        row = []
        for elevation in (10.0, 30.0, 60.0, 85.0):
            sky = PreethamSky(turbidity, direction_from_angles(np.radians(90 - elevation), 3.0))
            x, y = sky.zenith_chromaticity
            row.append(f"el {elevation:2.0f}: {sky.zenith_luminance_kcd_m2:6.2f} ({x:.3f}, {y:.3f})")
        print(f"  T = {turbidity:g}: " + "; ".join(row))

    rng = np.random.default_rng(0)
    d = rng.normal(size=(2000, 3))
    d[:, 2] = np.abs(d[:, 2])
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    grid, basis, _ = daylight_basis()
    weights = cmfs(VISIBLE_NM) * 683.0 * 5.0
    for rounded in (False, True):
        worst_xy = worst_y = 0.0
        for turbidity in (2.0, 3.0, 6.0, 10.0):
            for elevation in (5.0, 30.0, 70.0):
                sky = PreethamSky(turbidity, direction_from_angles(np.radians(90 - elevation), 1.0))
                if not rounded:
                    xyz = sky.radiance(d, VISIBLE_NM) @ weights
                else:
                    xy = sky.chromaticity(d)
                    m1, m2 = (np.round(m, 3) for m in daylight_m1_m2(xy[:, 0], xy[:, 1]))
                    s = (
                        np.interp(VISIBLE_NM, grid, basis[0])
                        + m1[:, None] * np.interp(VISIBLE_NM, grid, basis[1])
                        + m2[:, None] * np.interp(VISIBLE_NM, grid, basis[2])
                    )
                    xyz = s @ weights
                xy_back = xyz[:, :2] / xyz.sum(axis=-1, keepdims=True)
                worst_xy = max(worst_xy, np.abs(xy_back - sky.chromaticity(d)).max())
                worst_y = max(worst_y, np.abs(xyz[:, 1] / (1000.0 * sky.luminance(d)) - 1).max())
        if rounded:
            print(f"  same with M1/M2 rounded to 3 decimals (CIE tables, colour default): max |dxy| {worst_xy:.1e}")
        else:
            print(
                f"spectrum -> XYZ (5 nm sums) back to the model, M1/M2 unrounded (ours): "
                f"max |dxy| {worst_xy:.1e}, max |dY/Y| {worst_y:.1e}"
            )

    print("diffuse horizontal illuminance, Preetham sky (integrated) vs SPECTRL2 dhi, T = 3:")
    import pvlib

    n = 400
    mu = (np.arange(n) + 0.5) / n  # cos θ midpoints
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    theta = np.arccos(mu)
    dirs = direction_from_angles(theta[:, None], phi[None, :])
    for elevation in (15.0, 30.0, 60.0, 85.0):
        zenith = np.radians(90.0 - elevation)
        sky = PreethamSky(3.0, direction_from_angles(zenith, np.pi))
        # E = ∫ L cos θ dω = ∫∫ L μ dμ dφ.
        e_sky = np.sum(1000.0 * sky.luminance(dirs) * mu[:, None]) * (1.0 / n) * (np.pi / n)
        zdeg = np.array([90.0 - elevation])
        beta = ss.angstrom_beta(3.0)
        spectrl2 = pvlib.spectrum.spectrl2(
            apparent_zenith=zdeg,
            aoi=zdeg,
            surface_tilt=0.0,
            ground_albedo=0.2,
            surface_pressure=101325.0,
            relative_airmass=pvlib.atmosphere.get_relative_airmass(zdeg, model="kasten1966"),
            precipitable_water=2.0,
            ozone=0.35,
            aerosol_turbidity_500nm=beta * 0.5**-1.3,
            alpha=1.3,
            dayofyear=np.array([172]),
        )
        wl = spectrl2["wavelength"]
        dhi = np.interp(VISIBLE_NM, wl, np.asarray(spectrl2["dhi"])[:, 0])
        e_ref = illuminance_lx(dhi)
        print(
            f"  sun elevation {elevation:2.0f}: Preetham {e_sky / 1000:6.1f} klx, "
            f"SPECTRL2 {e_ref / 1000:6.1f} klx (ratio {e_sky / e_ref:.2f})"
        )

    sky = PreethamSky(3.0, sun_direction(30.0, 172, 10.5))
    d = rng.normal(size=(512 * 512, 3))
    wavelengths = np.linspace(380.0, 720.0, 16)
    start = time.perf_counter()
    sky.radiance(d, wavelengths)
    elapsed = time.perf_counter() - start
    print(
        f"speed: radiance of {d.shape[0]} directions x 16 wavelengths in {elapsed:.2f} s "
        f"({d.shape[0] * 16 / elapsed / 1e6:.0f} M values/s, one core)"
    )


def write_figures(directory: Path) -> None:
    from sandlight.sky.plots import plot_sky_day, plot_sky_dome

    directory.mkdir(parents=True, exist_ok=True)
    dome = plot_sky_dome(
        PreethamSky.from_location(3.0, 30.0, 172, 10.5), directory / "sky_dome_lat30_day172_t10.5.png", size=256
    )
    day = plot_sky_day(
        30.0, 172, [6.0, 8.0, 10.0, 12.0, 14.0, 16.0, 18.0], directory / "sky_day_lat30_day172.png", size=128, columns=7
    )
    print(f"\nwrote {dome} and {day}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", type=Path, help="directory for the example pictures")
    args = parser.parse_args()
    check_sun_position()
    check_sun_spectrum()
    check_sky()
    if args.figures is not None:
        write_figures(args.figures)


if __name__ == "__main__":
    main()
