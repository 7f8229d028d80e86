"""sandlight.calibration.tables: ρ(λ, k) tabulation, interpolation in log k, and resuming."""

import numpy as np
import pytest
from calibration_fakes import FakePowder, true_reflectance

from sandlight import calibration as cal
from sandlight.errors import ModelFileError, ParameterError

WL = np.array([400.0, 550.0, 700.0, 1000.0, 1500.0, 2500.0])
GRID = np.arange(-6.0, 0.51, 0.25)


@pytest.fixture
def member():
    return cal.end_members("hematite", ids=["GDS69.e"])[0]


def test_table_holds_the_forward_model_at_the_grid_points(member):
    fake = FakePowder(rays=10**12)
    table = cal.tabulate(member, fake, WL, GRID)
    assert table.rho.shape == table.stderr.shape == (WL.size, GRID.size)
    for j in (0, 7, GRID.size - 1):
        np.testing.assert_allclose(table.rho[:, j], true_reflectance(member, WL, 10 ** GRID[j]), atol=1e-5)
    assert fake.calls == GRID.size  # one run per trial k, all wavelengths at once


def test_interpolation_in_log_k_and_its_derivative(member):
    table = cal.tabulate(member, FakePowder(rays=10**12), WL, GRID)
    x = np.linspace(-5.9, 0.4, WL.size)  # one log10 k per wavelength, between grid points
    rho, drho = table(x)
    truth = np.array([true_reflectance(member, [w], 10**xi)[0] for w, xi in zip(WL, x)])
    np.testing.assert_allclose(rho, truth, atol=1e-3)
    h = 1e-5
    numeric = (table(x + h)[0] - table(x - h)[0]) / (2 * h)
    np.testing.assert_allclose(drho, numeric, rtol=1e-4, atol=1e-7)
    # Darker with more absorption, everywhere on the grid (the fake is monotone in k).
    assert np.all(np.diff(table.on_grid(np.linspace(-6, 0.5, 200)), axis=0) <= 1e-12)


def test_values_outside_the_grid_are_clipped_to_it(member):
    table = cal.tabulate(member, FakePowder(), WL, GRID)
    np.testing.assert_array_equal(table(np.full(WL.size, 3.0))[0], table.rho[:, -1])
    np.testing.assert_array_equal(table(np.full(WL.size, -9.0))[0], table.rho[:, 0])


def test_tabulation_resumes_from_its_cache(member, tmp_path):
    first = cal.tabulate(member, FakePowder(), WL, GRID, cache_dir=tmp_path)
    again = FakePowder()
    second = cal.tabulate(member, again, WL, GRID, cache_dir=tmp_path)
    assert again.calls == 0
    np.testing.assert_array_equal(first.rho, second.rho)
    assert len(list(tmp_path.glob("GDS69.e-*.npz"))) == 1


class Interrupted(Exception):
    pass


class FailingPowder(FakePowder):
    """Stops (as a killed run would) after ``columns`` k columns."""

    def __init__(self, columns):
        super().__init__()
        self.columns = columns

    def reflectance(self, member, wavelengths_nm, k):
        if self.calls == self.columns:
            raise Interrupted
        return super().reflectance(member, wavelengths_nm, k)


def test_an_interrupted_tabulation_computes_only_the_missing_columns(member, tmp_path):
    with pytest.raises(Interrupted):
        cal.tabulate(member, FailingPowder(columns=10), WL, GRID, cache_dir=tmp_path)
    finish = FakePowder()
    resumed = cal.tabulate(member, finish, WL, GRID, cache_dir=tmp_path)
    assert finish.calls == GRID.size - 10
    whole = cal.tabulate(member, FakePowder(), WL, GRID)
    np.testing.assert_array_equal(resumed.rho, whole.rho)
    assert not list(tmp_path.glob("*.part"))  # atomic writes leave no debris


def test_other_settings_get_their_own_cache_file(member, tmp_path):
    cal.tabulate(member, FakePowder(seed=0), WL, GRID, cache_dir=tmp_path)
    other = FakePowder(seed=1)
    cal.tabulate(member, other, WL, GRID, cache_dir=tmp_path)
    assert other.calls == GRID.size
    assert len(list(tmp_path.glob("*.npz"))) == 2


def test_a_corrupt_cache_file_is_refused_naming_it(member, tmp_path):
    cal.tabulate(member, FakePowder(), WL, GRID, cache_dir=tmp_path)
    path = next(tmp_path.glob("*.npz"))
    path.write_bytes(b"not an npz file")
    with pytest.raises(ModelFileError, match=path.name):
        cal.tabulate(member, FakePowder(), WL, GRID, cache_dir=tmp_path)


@pytest.mark.parametrize(
    "wavelengths, grid, name",
    [
        ([550.0, 450.0], GRID, "wavelengths_nm"),
        ([300.0, 550.0], GRID, "wavelengths_nm"),
        ([450.0, np.nan], GRID, "wavelengths_nm"),
        (WL, [-3.0, -2.0, -1.0], "log10_k"),
        (WL, [-3.0, -1.0, -2.0, 0.0], "log10_k"),
        (WL, [-20.0, -2.0, -1.0, 0.0], "log10_k"),
    ],
)
def test_bad_grids_are_refused(member, wavelengths, grid, name):
    with pytest.raises(ParameterError, match=name):
        cal.tabulate(member, FakePowder(), wavelengths, grid)
