"""Which spatial model gives a sample its shape: the family whose mesh holds it and whose base it
differs from least (sandlight.spatial.shipped), and Mesh.contains, which it relies on."""

import numpy as np
import pytest
import spatial_fakes
from spatial_fakes import RAYS, SLICES, STACKS

from sandlight.errors import ParameterError
from sandlight.sample import SandSample
from sandlight.spatial import Mesh, SpatialModel, model_for, shipped_model_paths, shipped_models
from sandlight.spatial.model import default_model_path

DUNE_BASE = SandSample(iron_oxide=0.02, hematite_ratio=0.5, grain_size=0.3, silt=0.02, clay=0.03)


@pytest.fixture(scope="module")
def dune_model():
    """A dry-dune family: iron oxide × grain size around a base unlike the default sample."""
    mesh = Mesh.grid(DUNE_BASE, iron_oxide=[0.005, 0.05], grain_size=[0.1, 0.6])
    nodes = spatial_fakes.measured_nodes(mesh, RAYS, stacks=STACKS, slices=SLICES, seed=5)
    return SpatialModel(n_components=2).fit(nodes, mesh)


def test_contains_follows_the_range_and_the_hull(beach_mesh, dune_model):
    assert beach_mesh.contains([[0.0], [1.0], [0.37]]).all()
    assert not beach_mesh.contains([[1.01]])[0] and not beach_mesh.contains([[np.nan]])[0]
    mesh = dune_model.mesh_
    inside, outside = DUNE_BASE.replace(iron_oxide=0.01), DUNE_BASE.replace(grain_size=0.8)
    np.testing.assert_array_equal(mesh.contains([inside, outside]), [True, False])
    # contains agrees with locate, which raises for the same point
    mesh.locate(inside)
    with pytest.raises(ParameterError, match="grain_size"):
        mesh.locate(outside)


def test_the_family_that_holds_the_sample_and_differs_least_answers(beach_model, dune_model):
    models = (beach_model, dune_model)
    # the dune family's own sand: its mesh holds it and nothing differs
    assert model_for(DUNE_BASE.replace(iron_oxide=0.01), models) is dune_model
    # the default mineralogy, wet: only the beach mesh holds saturation 0.5
    assert model_for(SandSample(saturation=0.5), models) is beach_model
    # a dune sand outside the dune mesh (grain size) falls back to the beach, which holds every sample
    assert model_for(DUNE_BASE.replace(grain_size=1.0), models) is beach_model
    # a tie goes to the earlier model
    assert model_for(SandSample(), (beach_model, beach_model)) is beach_model


def test_levels_share_one_model(beach_model, dune_model):
    """A scene's levels (here dry and wet dune sand) take the one model that holds them all: the
    dry family never lends its shape to wet sand, though the dune sand differs from its base in
    saturation alone and from the beach's in five parameters."""
    levels = [DUNE_BASE.replace(saturation=s) for s in (0.0, 0.5)]
    assert model_for(levels[:1], (beach_model, dune_model)) is dune_model
    assert model_for(levels, (beach_model, dune_model)) is beach_model
    assert model_for(levels[1:], (beach_model, dune_model)) is beach_model


def test_no_model_or_no_mesh_holding_the_sample_is_a_clear_error(dune_model):
    with pytest.raises(ParameterError, match="grain_size 0.1–0.6"):
        model_for(DUNE_BASE.replace(grain_size=1.0), (dune_model,))
    with pytest.raises(ParameterError, match="saturation"):
        model_for(DUNE_BASE.replace(saturation=0.2), (dune_model,))
    with pytest.raises(ParameterError, match="models"):
        model_for(SandSample(), ())
    with pytest.raises(ParameterError, match="samples"):
        model_for([], (dune_model,))


@pytest.mark.skipif(not default_model_path().is_file(), reason="shipped spatial models not trained yet")
def test_the_shipped_models_start_with_the_paper_beach():
    paths = shipped_model_paths()
    assert paths[0] == default_model_path()
    models = shipped_models()
    assert len(models) == len(paths)
    # every sample of the domain is held by some shipped model (the beach spans saturation 0-1)
    assert model_for(SandSample(saturation=0.3)).mesh_.contains(SandSample(saturation=0.3))[0]
    assert model_for(SandSample()) is models[0]


@pytest.mark.skipif(not default_model_path().is_file(), reason="shipped spatial models not trained yet")
@pytest.mark.parametrize(("family", "n_points"), [("dune", 1), ("wet", 2)])
def test_each_shipped_family_meets_its_held_out_check(family, n_points):
    """Issue 23's target is 5 % relative RMS at a held-out point: the dune family measures 4.3 %,
    the wet family 3.1 % and 3.3 % at its two points (docs/spatial-predictor.md)."""
    path = default_model_path().with_name(f"spatial-{family}.npz")
    if not path.is_file():
        pytest.skip(f"spatial-{family}.npz not shipped")
    model = next(m for p, m in zip(shipped_model_paths(), shipped_models()) if p == path)
    assert len(model.holdout_scores_) == n_points
    for score in model.holdout_scores_:
        assert score["relative_rms"] <= 0.05 and score["n_values"] >= 100, score["point"]
        # its held-out sample takes its shape from it, with nothing borrowed
        point = SandSample.from_dict({**model.mesh_.base, **score["point"]})
        assert model_for(point) is model and not model.mesh_.differing_parameters(point)
