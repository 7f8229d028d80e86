"""Shared inputs of the retrieval tests: the shipped bank and spectra it predicts."""

import numpy as np
import pytest

from sandlight.predictor import default_model
from sandlight.sample import SandSample


@pytest.fixture(scope="session")
def bank():
    return default_model()


@pytest.fixture(scope="session")
def dry_truth():
    return SandSample(iron_oxide=0.015, hematite_ratio=0.4)


@pytest.fixture(scope="session")
def dry_spectrum(bank, dry_truth):
    """The predictor's own (noiseless) spectrum of a dry reference sand."""
    return bank.wavelengths_.copy(), bank.predict([dry_truth])[0]


@pytest.fixture(scope="session")
def add_noise():
    """A spectrum (wl, r) with Gaussian noise of standard deviation sigma, fixed seed."""

    def noisy(spectrum, sigma, seed):
        wl, r = spectrum
        return wl, r + np.random.default_rng(seed).normal(0.0, sigma, r.size)

    return noisy
