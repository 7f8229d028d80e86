"""The spatial models shipped with sandlight, and which one gives a sample its BRDF shape.

Each shipped model covers one family of sand (docs/spatial-predictor.md, "Shipped models"): its
mesh varies a few parameters around a base sample. A sample takes its shape from the model
whose mesh holds its mesh coordinates, whose water matches (`MUST_MATCH`: a dry family never
lends its shape to wet sand) and whose base it differs from in the fewest other parameters;
ties go to the earlier model of `shipped_model_paths` (the paper's beach scene
first, so that every sample of the default mineralogy keeps the paper's model). The beach
model's mesh (saturation 0–1) holds every sample, so some model always answers; where the one
chosen still differs from the sample, `SpatialModel.brdf` says so
(`SpatialApproximationWarning`).

Public objects
--------------
shipped_model_paths
    The shipped model files, the default (beach) model first.
shipped_models
    The shipped models, loaded once.
model_for
    The shipped model that covers a sample, or every sample of a sequence at once.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from sandlight.errors import ParameterError
from sandlight.spatial.model import SpatialModel, default_model_path

if TYPE_CHECKING:
    from sandlight.sample import SandSample

__all__ = ["shipped_model_paths", "shipped_models", "model_for"]

#: File names of the shipped spatial models in the package's model folder.
SHIPPED_PATTERN = "spatial-*.npz"
#: Parameters a model must match (vary in its mesh, or hold at the sample's value): water changes
#: the shape of a sand's BRDF more than anything else (the flat water surfaces of filled pores,
#: docs/spatial-predictor.md), so a dry family never lends its shape to wet sand.
MUST_MATCH = ("saturation",)


def shipped_model_paths() -> tuple[Path, ...]:
    """The shipped spatial model files: the default (the paper's beach scene) first, the others
    by name. Empty when none is installed."""
    default = default_model_path()
    others = sorted(p for p in default.parent.glob(SHIPPED_PATTERN) if p.name != default.name)
    return ((default,) if default.is_file() else ()) + tuple(others)


@functools.lru_cache(maxsize=1)
def shipped_models() -> tuple[SpatialModel, ...]:
    """The shipped spatial models in the order of `shipped_model_paths` (loaded once, cached).

    Raises
    ------
    ModelFileError
        A shipped file is unreadable or not a spatial model.
    """
    return tuple(SpatialModel.load(p) for p in shipped_model_paths())


def model_for(
    samples: SandSample | Mapping | Sequence[SandSample | Mapping], models: Sequence[SpatialModel] | None = None
) -> SpatialModel:
    """The spatial model that covers ``samples`` (one sample, or all of a sequence at once, e.g.
    the levels of a scene, which then share one model).

    Of the ``models`` (default: `shipped_models`) whose mesh holds every sample and that match
    them in `MUST_MATCH`, the one whose base sample they differ from in the fewest parameters the
    mesh does not vary (counted over all the samples); ties go to the earlier model.

    Raises
    ------
    ParameterError
        No model holds every sample (the message lists the meshes), or no model is given.
    """
    from sandlight.sample import SandSample

    many = list(samples) if isinstance(samples, Sequence) and not isinstance(samples, str) else [samples]
    if not many or not all(isinstance(s, (SandSample, Mapping)) for s in many):
        raise ParameterError("samples", type(samples).__name__, "a SandSample, a dict or a non-empty sequence of them")
    candidates = tuple(shipped_models() if models is None else models)
    if not candidates:
        raise ParameterError("models", "none", "at least one spatial model (none is installed)")
    best, best_cost = None, np.inf
    for model in candidates:
        mesh = model.mesh_
        if not mesh.contains(many).all():
            continue
        differing = set().union(*(mesh.differing_parameters(s) for s in many))
        if differing & set(MUST_MATCH):
            continue
        if len(differing) < best_cost:
            best, best_cost = model, len(differing)
    if best is None:
        meshes = "; ".join(
            ", ".join(f"{p} {lo:g}–{hi:g}" for p, lo, hi in zip(m.mesh_.parameters, m.mesh_.lower, m.mesh_.upper))
            for m in candidates
        )
        raise ParameterError(
            "samples",
            f"{len(many)} sample(s)",
            f"samples inside a spatial model's mesh ({meshes}) and at its base's {', '.join(MUST_MATCH)} where the "
            "mesh does not vary it",
        )
    return best
