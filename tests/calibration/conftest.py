"""Shared fixtures of the calibration tests: the fake forward model is importable as a module;
the optical-table build script as a module."""

import importlib.util
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

SHARED_OPTICAL = SHARED_USGS.parents[1] / "optical" if SHARED_USGS is not None else None


def load_build_script():
    """scripts/data/build_optical_tables.py as a module (registered: its dataclasses need it)."""
    spec = importlib.util.spec_from_file_location("build_optical_tables", REPO / "scripts/data/build_optical_tables.py")
    module = sys.modules[spec.name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
