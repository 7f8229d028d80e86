"""Shared synthetic spatial models (small hemisphere, multinomial counts: fast and deterministic)."""

import pytest
import spatial_fakes
from spatial_fakes import RAYS, SLICES, STACKS

from sandlight.spatial import Mesh, SpatialModel


@pytest.fixture(scope="session")
def beach_mesh():
    return Mesh.beach(6)


@pytest.fixture(scope="session")
def beach_nodes(beach_mesh):
    return spatial_fakes.measured_nodes(beach_mesh, RAYS, stacks=STACKS, slices=SLICES, seed=3)


@pytest.fixture(scope="session")
def beach_model(beach_mesh, beach_nodes):
    return SpatialModel().fit(beach_nodes, beach_mesh, training_set={"synthetic": True})
