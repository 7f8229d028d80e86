"""Shared synthetic goniophotometer runs (multinomial draws from known BRDFs, fixed seeds)."""

import pytest

from sandlight.gonio import CollectorHemisphere, MeasuredBRDF
from sandlight.testing import synthetic_brdf

LAMBERT_ALBEDO = 0.6
CHANDRASEKHAR_OMEGA = 0.9
RAYS = 10**8  # cheap: the draws are multinomial per row, not per ray


@pytest.fixture(scope="session")
def hemisphere():
    return CollectorHemisphere()


@pytest.fixture(scope="session")
def lambert_probabilities(hemisphere):
    return synthetic_brdf.lambertian_probabilities(hemisphere, LAMBERT_ALBEDO)


@pytest.fixture(scope="session")
def lambert_counts(hemisphere, lambert_probabilities):
    return synthetic_brdf.sample_counts(hemisphere, lambert_probabilities, RAYS, seed=11)


@pytest.fixture(scope="session")
def chandrasekhar_probabilities(hemisphere):
    return synthetic_brdf.chandrasekhar_probabilities(hemisphere, CHANDRASEKHAR_OMEGA)


@pytest.fixture(scope="session")
def chandrasekhar_counts(hemisphere, chandrasekhar_probabilities):
    return synthetic_brdf.sample_counts(hemisphere, chandrasekhar_probabilities, RAYS, seed=12)


@pytest.fixture(scope="session")
def chandrasekhar_brdf(chandrasekhar_counts):
    return MeasuredBRDF.from_counts(
        **chandrasekhar_counts,
        sample={"medium": "isotropic", "omega": CHANDRASEKHAR_OMEGA},
        wavelength_nm=550.0,
        seed=12,
    )


@pytest.fixture(scope="session")
def lambert_albedo():
    return LAMBERT_ALBEDO


@pytest.fixture(scope="session")
def omega():
    return CHANDRASEKHAR_OMEGA
