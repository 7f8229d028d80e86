"""The spatial predictor: the shape of a sand sample's BRDF from its parameters (paper §3.2).

Modules
-------
mesh
    `Mesh`: nodes over a chosen subset of the sample parameters, barycentric location (eq. 6).
model
    `SpatialModel`: PCA of the node BRDFs, interpolation of the scores, reconstruction
    (eqs. 5, 7); `default_model()` is the shipped beach-scene model.
shipped
    The shipped models (one per family of sand) and `model_for`, the one that covers a sample.
training
    Node measurement as a restartable job, `train_spatial`, held-out `evaluate`.

The combined spectral × spatial BRDF is `sandlight.appearance.SandAppearance`.
"""

from sandlight.spatial.mesh import Mesh
from sandlight.spatial.model import (
    SpatialApproximationWarning,
    SpatialBRDF,
    SpatialModel,
    default_model,
    default_model_path,
)
from sandlight.spatial.shipped import model_for, shipped_model_paths, shipped_models
from sandlight.spatial.training import (
    HoldoutReport,
    cross_validate,
    evaluate,
    measure_nodes,
    node_brdfs,
    node_job,
    train_spatial,
)

__all__ = [
    "Mesh",
    "SpatialModel",
    "SpatialBRDF",
    "SpatialApproximationWarning",
    "default_model",
    "default_model_path",
    "model_for",
    "shipped_models",
    "shipped_model_paths",
    "HoldoutReport",
    "evaluate",
    "cross_validate",
    "measure_nodes",
    "node_brdfs",
    "node_job",
    "train_spatial",
]
