"""Batches of samples as columns: scalars broadcast, missing parameters take SandSample's defaults,
ambiguous input is refused (issue 24, "silent or surprising behaviour")."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from sandlight.errors import ParameterError
from sandlight.predictor import default_model
from sandlight.predictor.samples import sample_columns
from sandlight.sample import PARAMETERS, SandSample

IRON = np.array([0.005, 0.01, 0.02, 0.03, 0.04])
WATER = np.array([0.0, 0.2, 0.5, 0.8, 1.0])


def samples_of(**columns):
    """The same batch as SandSample objects, one per row."""
    n = len(next(v for v in columns.values() if np.ndim(v)))
    return [SandSample(**{k: v[i] if np.ndim(v) else v for k, v in columns.items()}) for i in range(n)]


class TestColumns:
    def test_every_parameter_in_order_with_defaults(self):
        columns = sample_columns({"iron_oxide": IRON})
        assert list(columns) == [p.name for p in PARAMETERS]
        for p in PARAMETERS:
            expected = IRON if p.name == "iron_oxide" else np.full(len(IRON), p.default)
            np.testing.assert_array_equal(columns[p.name], expected)
        assert columns["depth_mm"].dtype == float and np.isinf(columns["depth_mm"]).all()

    def test_scalars_broadcast_against_arrays(self):
        columns = sample_columns({"iron_oxide": IRON, "iron_oxide_form": "particles", "porosity": 0.35})
        assert columns["iron_oxide_form"].tolist() == ["particles"] * 5
        np.testing.assert_array_equal(columns["porosity"], np.full(5, 0.35))

    def test_all_containers_agree(self):
        frame = pd.DataFrame({"iron_oxide": IRON, "saturation": WATER, "id": np.arange(5)})  # extra column ignored
        structured = np.array(list(zip(IRON, WATER)), dtype=[("iron_oxide", float), ("saturation", float)])
        dataset = xr.Dataset({"iron_oxide": ("sample", IRON), "saturation": ("sample", WATER)})
        rows = [{"iron_oxide": a, "saturation": b} for a, b in zip(IRON, WATER)]
        expected = sample_columns(samples_of(iron_oxide=IRON, saturation=WATER))
        for batch in (frame, structured, dataset, rows, {"iron_oxide": IRON, "saturation": WATER}):
            got = sample_columns(batch)
            for name, column in expected.items():
                np.testing.assert_array_equal(got[name], column, err_msg=f"{type(batch).__name__} {name}")

    def test_one_sample(self):
        for one in (SandSample(iron_oxide=0.02), {"iron_oxide": 0.02}):
            columns = sample_columns(one)
            assert columns["iron_oxide"].tolist() == [0.02] and columns["grain_size"].tolist() == [0.25]

    @pytest.mark.parametrize(
        "batch, name, allowed",
        [
            ({"iron_oxide": np.zeros(3), "saturation": np.zeros(4)}, "saturation", "3 values like iron_oxide"),
            ({"iron_oxide": np.zeros(3), "saturation": np.zeros(1)}, "saturation", "or a scalar for all"),
            ({"iron_oxide": np.zeros((2, 3))}, "iron_oxide", "a scalar or a 1-D array"),
            ({"iron_oxide": [[0.1, 0.2], [0.3]]}, "iron_oxide", "a scalar or a 1-D array"),
            ({"iron_oxde": np.zeros(3)}, "iron_oxde", "a sample parameter"),
            ([{"iron_oxide": 0.01}, {"saturaton": 0.5}], "saturaton", "a sample parameter"),
            ({"iron_oxide": [True, False]}, "iron_oxide", "not bools"),
            ([{"saturation": True}], "saturation", "not a bool"),
            ({"grain_size": ["fine", "coarse"]}, "grain_size", "a number"),
            (np.zeros((2, 2), dtype=[("iron_oxide", float)]), "samples", "a 1-D structured array"),
            ([], "samples", "a non-empty list"),
            ("red-dune", "samples", "SandSample"),
        ],
    )
    def test_ambiguous_input_is_refused(self, batch, name, allowed):
        with pytest.raises(ParameterError) as info:
            sample_columns(batch)
        assert info.value.name == name and allowed in info.value.allowed

    def test_long_arrays_are_not_echoed_whole(self):
        with pytest.raises(ParameterError) as info:
            sample_columns({"iron_oxide": np.array(["x"] * 10**5)})
        assert len(str(info.value)) < 300


class TestShippedBank:
    """The defects of the tour, through ``default_model().predict``."""

    def test_a_scalar_form_with_arrays_gives_one_row_per_sample(self):
        bank = default_model()
        batch = {"iron_oxide": IRON, "saturation": WATER, "iron_oxide_form": "particles"}
        r = bank.predict(batch)
        assert r.shape == (5, len(bank.wavelengths_))  # was (1, n_wl)
        np.testing.assert_array_equal(r, bank.predict(samples_of(**batch)))
        assert len(np.unique(r, axis=0)) == 5

    @pytest.mark.parametrize("container", [dict, pd.DataFrame])
    def test_only_some_parameters_take_the_defaults(self, container):
        bank = default_model()
        r = bank.predict(container({"iron_oxide": IRON, "saturation": WATER}))  # was "depth_mm = None"
        np.testing.assert_array_equal(r, bank.predict(samples_of(iron_oxide=IRON, saturation=WATER)))

    def test_arrays_of_different_lengths_are_refused(self):
        with pytest.raises(ParameterError, match="saturation.*3 values like iron_oxide"):
            default_model().predict({"iron_oxide": IRON[:3], "saturation": WATER[:2]})
