"""Predictors that replace hours of Monte Carlo by an explicit formula (paper §3).

Public objects
--------------
SpectralModel, evaluate, HoldoutReport
    The spectral predictor r(x) ≈ r̄ + U_k Wᵀ φ(x) (:mod:`sandlight.predictor.spectral`).
ModelBank, default_model, full_range_model
    Several models, each sample predicted by the most accurate one covering it; the shipped
    banks, the paper's 400–700 nm and the full range 350–2500 nm (:mod:`sandlight.predictor.bank`).
predict
    ``sandlight.predict``: the bank at any wavelength it spans, with the answering model and its
    hold-out error, as an xarray Dataset (:mod:`sandlight.predictor.prediction`).
Domain, Dimension
    Training domains over SandSample parameters (:mod:`sandlight.predictor.domain`).
generate_training_set, fit_training_set, train_spectral
    Training data (a restartable job) and the fitting pipeline
    (:mod:`sandlight.predictor.training`).
ModelVersionWarning
    A model file written by another sandlight version was loaded.

Shared by the spectral and the spatial predictor: the estimator base (parameters, constraints,
fitted state, save/load: :mod:`sandlight.predictor.estimator`), the model-file format
(:mod:`sandlight.predictor.model_file`), PCA of noisy Monte Carlo data
(:mod:`sandlight.predictor.pca`) and batches of samples as columns
(:mod:`sandlight.predictor.samples`).
"""

from sandlight.predictor.bank import ModelBank, default_model, full_range_model
from sandlight.predictor.domain import Dimension, Domain
from sandlight.predictor.model_file import ModelVersionWarning
from sandlight.predictor.prediction import predict
from sandlight.predictor.spectral import HoldoutReport, SpectralModel, evaluate
from sandlight.predictor.training import fit_training_set, generate_training_set, train_spectral, wavelength_grid

__all__ = [
    "SpectralModel",
    "evaluate",
    "HoldoutReport",
    "ModelVersionWarning",
    "ModelBank",
    "default_model",
    "full_range_model",
    "predict",
    "Domain",
    "Dimension",
    "generate_training_set",
    "fit_training_set",
    "train_spectral",
    "wavelength_grid",
]
