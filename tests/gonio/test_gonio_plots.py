import math
import os

import numpy as np
import pytest
from PIL import Image

from sandlight.errors import ParameterError
from sandlight.gonio import CollectorHemisphere, MeasuredBRDF
from sandlight.gonio.plots import plot_outgoing_polar, plot_principal_plane, save_overview_png
from sandlight.testing import synthetic_brdf


@pytest.fixture(scope="module")
def lambert_exact():
    h = CollectorHemisphere(7, 6)
    p = synthetic_brdf.lambertian_probabilities(h, 0.5)
    launched = np.full(h.n_patches, 10**12)
    counts = np.round(p * 10**12).astype(np.int64)
    return MeasuredBRDF.from_counts(counts, launched - counts.sum(axis=1), launched, stacks=7, slices=6)


def test_overview_png(tmp_path, chandrasekhar_brdf):
    path = save_overview_png(chandrasekhar_brdf, tmp_path / "brdf.png", dpi=60)
    assert os.listdir(tmp_path) == ["brdf.png"]
    with Image.open(path) as im:
        assert im.format == "PNG" and im.size == (660, 270)


def test_polar_map_shows_the_continuous_brdf(chandrasekhar_brdf):
    ax = plot_outgoing_polar(chandrasekhar_brdf, 40.0, resolution=30)
    values = ax.collections[0].get_array()
    assert values.size == 30 * 120
    # Chandrasekhar's BRDF grows towards grazing exit: the outer ring is brighter than the centre.
    grid = np.asarray(values).reshape(30, 120)
    assert grid[-1].mean() > 1.2 * grid[0].mean()


def test_principal_plane_curves(lambert_exact):
    ax = plot_principal_plane(lambert_exact, (0, 20, 70))
    assert len(ax.lines) == 3 + 1  # three incidences and the vertical θ_v = 0 line
    for line in ax.lines[:3]:
        np.testing.assert_allclose(line.get_ydata(), 0.5 / math.pi, rtol=1e-9)


@pytest.mark.parametrize("zenith", [-1.0, 90.0, "steep"])
def test_invalid_zenith(lambert_exact, zenith):
    with pytest.raises(ParameterError, match="zenith_deg"):
        plot_outgoing_polar(lambert_exact, zenith)
    with pytest.raises(ParameterError, match="zenith_deg"):
        plot_principal_plane(lambert_exact, [10.0, zenith])
