"""Plots of a measured BRDF: what a user looks at first.

Public objects
--------------
plot_outgoing_polar
    Polar heat map of the outgoing BRDF for one incidence (zenith as radius, azimuth as angle).
plot_principal_plane
    BRDF along the principal plane for several incidence angles.
save_overview_png
    Both plots side by side in one PNG, written atomically.

All plots evaluate the continuous BRDF (`MeasuredBRDF.f`, paper §3.2.4). Conventions: the
light comes from azimuth φ_i = 0 (the +x side); in the principal plane the signed viewing angle
θ_v is negative on the light's side (backscatter, θ_v = −θ_i is the retro-reflection
direction) and positive on the far side (forward scatter, θ_v = +θ_i is the mirror direction).
Matplotlib is used through `matplotlib.figure.Figure`, without pyplot's global state.
"""

from __future__ import annotations

import math
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.gonio.brdf import MeasuredBRDF
from sandlight.io import write_atomically

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_outgoing_polar", "plot_principal_plane", "save_overview_png"]


def _check_zenith(name: str, value: object) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "must be a zenith angle in [0, 90) degrees") from None
    if not 0.0 <= v < 90.0:
        raise ParameterError(name, value, "must be a zenith angle in [0, 90) degrees")
    return v


def _incident(zenith_deg: float) -> np.ndarray:
    t = math.radians(zenith_deg)
    return np.array([math.sin(t), 0.0, math.cos(t)])


def _label(normalised: bool) -> str:
    return "normalised BRDF f̂ (sr⁻¹)" if normalised else "BRDF f (sr⁻¹)"


def plot_outgoing_polar(
    brdf: MeasuredBRDF, zenith_deg: float, *, normalised: bool = False, ax: Axes | None = None, resolution: int = 90
) -> Axes:
    """Polar heat map of f(ω_i, ω_o) over the outgoing hemisphere for one incidence.

    Parameters
    ----------
    brdf : MeasuredBRDF
    zenith_deg : float
        Incident zenith angle θ_i in degrees, [0, 90); the light is at azimuth 0.
    normalised : bool, default False
        Plot the normalised BRDF (unit reflectance at normal incidence) instead of the absolute.
    ax : matplotlib polar Axes, optional
        Axes to draw in (``projection='polar'``); a new figure is made if None.
    resolution : int, default 90
        Number of zenith rings (azimuth uses 4× as many steps).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.figure import Figure

    theta_i = _check_zenith("zenith_deg", zenith_deg)
    if ax is None:
        ax = Figure(figsize=(5, 4.5)).add_subplot(projection="polar")
    theta_edges = np.linspace(0.0, 90.0, resolution + 1)
    phi_edges = np.linspace(0.0, 2 * math.pi, 4 * resolution + 1)
    theta_c = np.radians(0.5 * (theta_edges[1:] + theta_edges[:-1]))
    phi_c = 0.5 * (phi_edges[1:] + phi_edges[:-1])
    tt, pp = np.meshgrid(theta_c, phi_c, indexing="ij")
    wo = np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt)], axis=-1)
    values = brdf.f(_incident(theta_i), wo, normalised=normalised)
    mesh = ax.pcolormesh(phi_edges, theta_edges, values, shading="flat", cmap="viridis")
    ax.set_ylim(0, 90)
    ax.set_yticks([30, 60, 90])
    ax.set_yticklabels(["30°", "60°", "90°"])
    ax.plot([0.0], [theta_i], marker="*", color="white", markeredgecolor="black", markersize=12, linestyle="none")
    ax.set_title(f"outgoing BRDF, incidence θ_i = {theta_i:g}° (★ = light)")
    ax.figure.colorbar(mesh, ax=ax, label=_label(normalised), shrink=0.8)
    return ax


def plot_principal_plane(
    brdf: MeasuredBRDF,
    zenith_deg: ArrayLike = (0.0, 30.0, 60.0),
    *,
    normalised: bool = False,
    ax: Axes | None = None,
    samples: int = 181,
) -> Axes:
    """BRDF along the principal plane for several incident zenith angles.

    Parameters
    ----------
    brdf : MeasuredBRDF
    zenith_deg : sequence of float, default (0, 30, 60)
        Incident zenith angles in degrees, each in [0, 90).
    normalised : bool, default False
        Plot the normalised BRDF instead of the absolute.
    ax : matplotlib Axes, optional
    samples : int, default 181
        Viewing angles from −89.5° to 89.5°.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.figure import Figure

    zeniths = [_check_zenith("zenith_deg", z) for z in np.atleast_1d(np.asarray(zenith_deg, dtype=object))]
    if ax is None:
        ax = Figure(figsize=(6, 4.5)).add_subplot()
    view = np.linspace(-89.5, 89.5, samples)
    v = np.radians(view)
    # θ_v < 0: towards the light (+x); θ_v > 0: away from it (−x).
    wo = np.stack([-np.sin(v), np.zeros_like(v), np.cos(v)], axis=-1)
    for z in zeniths:
        ax.plot(view, brdf.f(_incident(z), wo, normalised=normalised), label=f"θ_i = {z:g}°")
    ax.axvline(0.0, color="0.8", linewidth=0.8)
    ax.set_xlim(-90, 90)
    ax.set_xlabel("viewing angle θ_v (°): < 0 towards the light, > 0 forward")
    ax.set_ylabel(_label(normalised))
    ax.set_title("principal plane")
    ax.legend()
    return ax


def save_overview_png(
    brdf: MeasuredBRDF,
    path: str | PathLike,
    *,
    zenith_deg: float = 30.0,
    principal_zenith_deg: ArrayLike = (0.0, 30.0, 60.0),
    normalised: bool = False,
    dpi: int = 120,
) -> Path:
    """Write the polar heat map and the principal-plane curves side by side as a PNG.

    Parameters
    ----------
    brdf : MeasuredBRDF
    path : str or os.PathLike
        Destination PNG; written to a temporary file and moved into place (``os.replace``).
    zenith_deg : float, default 30
        Incidence of the polar heat map, degrees in [0, 90).
    principal_zenith_deg : sequence of float, default (0, 30, 60)
        Incidences of the principal-plane curves.
    normalised : bool, default False
    dpi : int, default 120

    Returns
    -------
    pathlib.Path
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 4.5), layout="constrained")
    plot_outgoing_polar(brdf, zenith_deg, normalised=normalised, ax=fig.add_subplot(1, 2, 1, projection="polar"))
    plot_principal_plane(brdf, principal_zenith_deg, normalised=normalised, ax=fig.add_subplot(1, 2, 2))
    wl = "" if brdf.wavelength_nm is None else f", λ = {brdf.wavelength_nm:g} nm"
    fig.suptitle(f"sandlight BRDF ({brdf.rays:.3g} trials{wl}, R(0°) = {brdf.normal_reflectance:.3f})")
    return write_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi), make_dirs=False)
