"""Shared appearance fixtures: a synthetic spatial model (7 × 8 hemisphere, multinomial counts) and
spectral model (tests/spatial/spatial_fakes.py), and two appearances built from them."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent.parent / "spatial"))
import spatial_fakes  # noqa: E402
from appearance_helpers import SLICES, STACKS  # noqa: E402

from sandlight.appearance import SandAppearance  # noqa: E402
from sandlight.sample import SandSample  # noqa: E402
from sandlight.spatial import Mesh, SpatialModel  # noqa: E402


@pytest.fixture(scope="module")
def spatial():
    mesh = Mesh.beach(6)
    return SpatialModel(n_components=3).fit(
        spatial_fakes.measured_nodes(mesh, 10**8, stacks=STACKS, slices=SLICES, seed=5), mesh
    )


@pytest.fixture(scope="module")
def spectral():
    return spatial_fakes.fitted_spectral_model()


@pytest.fixture(scope="module")
def app(spatial):
    # A bright spectrum (0.55–0.9) on the saturation-0.3 point: r(λ) is above r_0 at every λ.
    return SandAppearance(SandSample(saturation=0.3), spatial_fakes.fake_spectrum, spatial)


@pytest.fixture(scope="module")
def product(spatial):
    return SandAppearance(SandSample(saturation=0.3), spatial_fakes.fake_spectrum, spatial, combination="product")
