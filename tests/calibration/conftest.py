"""Shared fixtures of the calibration tests: the fake forward model is importable as a module."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

REPO = Path(__file__).resolve().parents[2]
SHARED_USGS = next(
    (p / "shared" / "data" / "measured" / "usgs_splib07a" for p in REPO.parents if (p / "shared").is_dir()), None
)

needs_shared = pytest.mark.skipif(
    SHARED_USGS is None or not SHARED_USGS.is_dir(), reason="shared USGS splib07a folder not available"
)
