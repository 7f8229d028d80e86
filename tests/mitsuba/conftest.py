"""Fixtures of the Mitsuba tests: the plugin in a given variant, skipped (with the reason) where
Mitsuba or LLVM is missing. `.ci/run` installs both, so CI runs these tests."""

from __future__ import annotations

import importlib.util

import pytest

from sandlight.mitsuba import find_libllvm

MISSING_MITSUBA = "Mitsuba 3 is not installed (pip install 'sandlight[mitsuba]'; .ci/run installs it)"
MISSING_LLVM = "no LLVM >= 16 for Dr.Jit's llvm variants (apt-get install libllvm19; .ci/run installs it)"


@pytest.fixture(scope="session")
def load_variant():
    """``load_variant(name)`` sets the Mitsuba variant, registers `sand`, returns ``mitsuba``."""
    if importlib.util.find_spec("mitsuba") is None:
        pytest.skip(MISSING_MITSUBA)
    if find_libllvm() is None:
        pytest.skip(MISSING_LLVM)
    from sandlight.mitsuba import load_mitsuba

    return load_mitsuba


@pytest.fixture
def rgb(load_variant):
    return load_variant("llvm_ad_rgb")


@pytest.fixture
def spectral(load_variant):
    return load_variant("llvm_ad_spectral")
