"""Fixtures of the colour tests (helpers live in colour_fakes.py)."""

from __future__ import annotations

import pytest
from colour_fakes import FakeProvider, FakeSample

from sandlight.errors import SandlightError


@pytest.fixture
def fake_sample():
    return FakeSample()


@pytest.fixture
def fake_provider():
    return FakeProvider()


@pytest.fixture(params=["default-predictor", "engine"])
def real_provider(request):
    """The real reflectance provider for physics trend tests; skipped until one ships."""
    from sandlight.colour.provider import default_reflectance_provider

    try:
        from sandlight.sample import SandSample  # noqa: F401
    except ImportError as exc:
        pytest.skip(f"physics trend needs sandlight.sample.SandSample, not importable ({exc})")
    if request.param == "engine":
        from sandlight.colour.provider import engine_reflectance_provider

        # 4000 rays: standard errors ≤ 0.008 per band, far below the trends' size.
        return engine_reflectance_provider(4000, threads=1)
    try:
        return default_reflectance_provider()
    except SandlightError as exc:
        pytest.skip(f"physics trend needs the shipped spectral predictor: {exc}")
