"""The gravity-settled surface of the explicit reference (docs/geometry.md, issue 9 item 1).

Monodisperse spheres d = 0.25 mm in a 2 mm × 2 mm × 2 mm periodic box (seed 7), with 4
reference-grain layers' worth of grains settled on the cut (about 290 grains).
"""

import itertools
import math

import numpy as np
import pytest

from sandlight import _native
from sandlight.errors import ParameterError
from sandlight.physics.packing import generate_packing, grain_medium

pytestmark = pytest.mark.skipif(not hasattr(_native, "Packing"), reason="native extension without explicit geometry")

D_MM = 0.25
BOX = dict(reference_mm=D_MM, lateral_mm=2.0, depth_mm=2.0, seed=7)


@pytest.fixture(scope="module")
def settled():
    return generate_packing(grain_medium([D_MM]), surface="settled", settled_layers=4.0, **BOX)


def _neighbours(pk):
    """Centres and diameters of every grain a deposited one can touch: the packed grains (all
    have centres below the cut plane z = H) and the deposited ones, with their images in x, y."""
    packed, d_packed = pk.particles()
    dep, d_dep = pk.deposited()
    centres, diameters = np.vstack([packed, dep]), np.concatenate([d_packed, d_dep])
    lx, ly, _ = pk.period_mm
    shifts = [np.array([i * lx, j * ly, 0.0]) for i, j in itertools.product((-1, 0, 1), repeat=2)]
    return np.vstack([centres + s for s in shifts]), np.tile(diameters, len(shifts))


def _gaps(pk):
    """For each deposited grain: gaps (mm) to every neighbour image but itself, and their centres."""
    dep, d_dep = pk.deposited()
    centres, diameters = _neighbours(pk)
    for x, d in zip(dep, d_dep):
        dist = np.linalg.norm(centres - x, axis=1)
        other = dist > 1e-12
        yield x, d, dist[other] - 0.5 * (d + diameters[other]), centres[other]


def test_settled_spheres_do_not_overlap(settled):
    assert settled.surface == "settled" and settled.n_deposited > 200
    # Exact for spheres: no pair closer than the sum of radii by more than 1e-6 d.
    worst = max(-g.min() / d for _, d, g, _ in _gaps(settled))
    assert worst <= 1e-6, worst


def _balanced(normals):
    """Whether gravity is balanced by non-negative forces along the given contact normals:
    ẑ = Σ fᵢ nᵢ with fᵢ ≥ 0 (to 1e-9) for some three of them, or for two when ẑ lies in their
    plane (a grain at the bottom of a groove)."""
    up = np.array([0.0, 0.0, 1.0])
    for k in (2, 3):
        for sub in itertools.combinations(normals, k):
            n = np.array(sub).T
            f, *_ = np.linalg.lstsq(n, up, rcond=None)
            if np.all(f >= -1e-9) and np.linalg.norm(n @ f - up) < 1e-9:
                return True
    return False


def test_every_settled_sphere_rests_on_contacts_that_hold_it(settled):
    # Contacts: neighbours within 1e-6 d. Every deposited sphere has at least three, and gravity
    # is balanced by non-negative contact forces along their normals: with the supporting
    # centres below it, the vertical through its centre passes inside their triangle
    # (Visscher & Bolsterli's rule).
    for x, d, gaps, centres in _gaps(settled):
        touching = gaps <= 1e-6 * d
        normals = (x - centres[touching]) / np.linalg.norm(x - centres[touching], axis=1)[:, None]
        assert touching.sum() >= 3, (x, gaps[touching])
        assert _balanced(normals), (x, normals)


def test_settled_layer_is_looser_than_the_bulk(settled):
    # Packing fraction from 9 planes 0.5–2.5 grains above the cut plane (the deposit reaches
    # ~4 grains higher), 20 000 random points each. Visscher & Bolsterli's deposit of equal
    # spheres packs at 0.582; over 8 seeds this box gives 0.582 ± 0.004 (sd), so 0.565–0.595
    # holds it within 4 sd while staying clearly below the bulk's 0.600.
    h = settled.period_mm[2]
    porosity, overlap = settled.porosity_profile(h + np.linspace(0.5, 2.5, 9) * D_MM, 20_000, 3)
    eta = 1.0 - porosity.mean()
    assert 0.565 < eta < 0.595, eta
    assert np.all(overlap == 0.0)
    # Well below the cut plane the bulk packing is untouched.
    bulk, _ = settled.porosity_profile(h - np.linspace(2.0, 6.0, 9) * D_MM, 20_000, 3)
    assert 1.0 - bulk.mean() == pytest.approx(0.60, abs=0.01)
    # The surface: every vertical line meets a grain, under the plane where rays start.
    heights = settled.surface_heights(2000, 1)
    assert np.all(np.isfinite(heights)) and heights.max() < settled.top_mm
    dep, d_dep = settled.deposited()
    assert settled.top_mm >= (dep[:, 2] + d_dep / 2).max()


def test_transparent_settled_sample_reflects_everything(settled):
    # Non-absorbing, semi-infinite: every ray escapes unless capped by the event limit.
    launched, escaped, absorbed, transmitted, capped, _ = (
        grain_medium([D_MM]).explicit(settled).dhr(0.0, 3, 0, 0, 2000, 20_000, 10_000, None)
    )
    assert absorbed == transmitted == 0
    assert escaped == launched - capped
    assert capped < 0.05 * launched


def test_cut_surface_is_unchanged_without_the_new_arguments():
    plain = generate_packing(grain_medium([D_MM]), **BOX)
    cut = generate_packing(grain_medium([D_MM]), surface="cut", **BOX)
    assert plain.surface == cut.surface == "cut" and plain.n_deposited == cut.n_deposited == 0
    for a, b in zip(plain.particles(), cut.particles()):
        np.testing.assert_array_equal(a, b)
    medium = grain_medium([D_MM], alpha_per_mm=0.5)
    counts = [medium.explicit(pk).dhr(0.0, 5, 0, 0, 3000, 10_000_000, 10_000, None) for pk in (plain, cut)]
    assert counts[0] == counts[1]
    assert plain.top_mm == pytest.approx(plain.period_mm[2] + D_MM / 2, rel=1e-12)


def test_settled_and_cut_share_the_packing_below_the_deposit(settled):
    cut = generate_packing(grain_medium([D_MM]), **BOX)
    dep, d_dep = settled.deposited()
    below = (dep[:, 2] - d_dep / 2).min() - 0.01
    # Also where images of the deposit one period down would be, if it were periodic in z.
    heights = np.linspace(0.05, below, 12)
    np.testing.assert_array_equal(
        settled.porosity_profile(heights, 5000, 2)[0], cut.porosity_profile(heights, 5000, 2)[0]
    )


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(surface="pile"), "surface"),
        (dict(surface=None), "surface"),
        (dict(surface="settled", settled_layers=0.0), "settled_layers"),
        (dict(surface="settled", settled_layers=math.nan), "settled_layers"),
        (dict(surface="settled", settled_layers="two"), "settled_layers"),
        (dict(surface="settled", settled_layers=100.0), "settled_layers"),
    ],
)
def test_bad_surface_arguments_raise(kwargs, name):
    with pytest.raises(ParameterError, match=name) as e:
        generate_packing(grain_medium([D_MM]), reference_mm=D_MM, lateral_mm=1.5, depth_mm=1.5, **kwargs)
    assert e.value.name == name


def test_native_surface_arguments_are_checked():
    m = grain_medium([D_MM])
    with pytest.raises(ParameterError, match="settled_thickness_mm"):
        _native.Packing.generate(m, 1.5, 1.5, surface="settled")
    with pytest.raises(ParameterError, match="settled_thickness_mm"):
        _native.Packing.generate(m, 1.5, 1.5, surface="cut", settled_thickness_mm=0.5)
    with pytest.raises(ParameterError, match="surface"):
        _native.Packing.generate(m, 1.5, 1.5, surface="heap", settled_thickness_mm=0.5)
    with pytest.raises(ParameterError, match="settled_thickness_mm"):
        _native.Packing.generate(m, 1.5, 1.5, surface="settled", settled_thickness_mm=5.0)
