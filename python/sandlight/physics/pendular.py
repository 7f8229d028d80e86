"""Pendular water: how much of the grain surface the first water of a damp sand wets.

At low saturation the water of a sand sits in pendular rings (menisci) around the contacts of
the grains (Fisher 1926), not as a film of one thickness on every surface. Each ring wets a
spherical cap on each of its two grains. This module gives the wetted fraction of the surface
for a degree of saturation. The engine puts the film only on that fraction of the particle
surface facing an air-filled pore (docs/model.md §2.5).

Geometry (equal spheres of radius R in contact, perfect wetting, the meniscus a circular arc —
the toroidal approximation of Fisher 1926): a ring whose edge on each sphere lies at the
half-angle β from the contact axis holds

    V(β) = 2π R³ (sec β − 1)² [1 − (π/2 − β) tan β]

and wets a cap of area 2π R² (1 − cos β) on each sphere. With N_c contacts per grain
(:data:`CONTACTS`) and porosity φ, the saturation and the wetted fraction are

    S = (N_c/2) V(β) / [(φ/(1 − φ)) (4/3) π R³],    f = N_c (1 − cos β) / 2.

R drops out. ``tests/physics/test_pendular.py`` checks V(β) against a numerical integral of the
toroidal ring's profile.

References
----------
Fisher, R. A. (1926). On the capillary forces in an ideal soil; correction of formulae given by
W. B. Haines. *J. Agric. Sci.* 16, 492–505.
"""

from __future__ import annotations

import math

from scipy.optimize import brentq

__all__ = ["CONTACTS", "ring_volume", "ring_saturation", "wetted_fraction", "film_coverage"]

#: Mean contact number of a random packing of spheres. 6 is the isostatic value of random
#: close packing. Loose frictional packings have somewhat fewer contacts (docs/model.md §2.5).
CONTACTS = 6.0

#: Largest ring half-angle considered (60°). Beyond it rings of neighbouring contacts overlap
#: for any N_c ≥ 4, and every wetted fraction there exceeds 1 anyway.
_BETA_MAX = math.pi / 3.0


def ring_volume(beta: float) -> float:
    """V(β)/R³ of a pendular ring between two touching spheres (toroidal approximation)."""
    return 2.0 * math.pi * (1.0 / math.cos(beta) - 1.0) ** 2 * (1.0 - (math.pi / 2.0 - beta) * math.tan(beta))


def ring_saturation(beta: float, porosity: float, contacts: float = CONTACTS) -> float:
    """The degree of saturation when every contact holds a ring of half-angle β."""
    pore_volume = porosity / (1.0 - porosity) * 4.0 / 3.0 * math.pi
    return 0.5 * contacts * ring_volume(beta) / pore_volume


def wetted_fraction(beta: float, contacts: float = CONTACTS) -> float:
    """Fraction of a grain's surface inside the wetted caps of its N_c rings (not capped at 1)."""
    return 0.5 * contacts * (1.0 - math.cos(beta))


def film_coverage(saturation: float, porosity: float, contacts: float = CONTACTS) -> float:
    """Wetted fraction of the grain surface when pendular rings hold ``saturation``, in [0, 1].

    0 for a dry sample; 1 once the rings would wet the whole surface (or β would pass 60°).
    """
    if saturation <= 0.0:
        return 0.0
    if saturation >= ring_saturation(_BETA_MAX, porosity, contacts):
        return 1.0
    beta = brentq(lambda b: ring_saturation(b, porosity, contacts) - saturation, 1e-9, _BETA_MAX, xtol=1e-12)
    return min(1.0, wetted_fraction(beta, contacts))
