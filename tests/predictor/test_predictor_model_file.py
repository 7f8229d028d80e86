"""Model files: save → load → identical predictions; damaged or foreign files refused."""

import json
import zipfile

import numpy as np
import pytest
from test_predictor_spectral import SMALL, WL, exact_cubic_problem

import sandlight
import sandlight.predictor.bank as bank
from sandlight.errors import ModelFileError, SandlightError
from sandlight.predictor import Dimension, Domain, ModelVersionWarning, SpectralModel, default_model


@pytest.fixture(scope="module")
def model():
    train, R, _, _ = exact_cubic_problem(SMALL, 300, seed=3)
    m = SpectralModel(ridge=1e-9).fit(
        train, R, wavelengths_nm=WL, domain=SMALL, training_set={"path": "somewhere/dataset.nc", "seed": 3}
    )
    m.holdout_scores_ = {"rms_error_overall": 0.001}
    m.name_, m.description_ = "small", "a test model"
    return m


@pytest.fixture
def saved(model, tmp_path):
    return model.save(tmp_path / "model.npz")


def rewrite(src, dst, change):
    """Copy an npz file, letting ``change(name, array)`` replace or drop (None) members."""
    with np.load(src, allow_pickle=False) as npz:
        members = {k: change(k, npz[k]) for k in npz.files}
    with open(dst, "wb") as fh:
        np.savez(fh, **{k: v for k, v in members.items() if v is not None})
    return dst


def with_metadata(src, dst, **updates):
    def change(name, array):
        if name != "metadata":
            return array
        meta = json.loads(str(array[()]))
        meta.update(updates)
        return np.array(json.dumps(meta))

    return rewrite(src, dst, change)


class TestRoundTrip:
    def test_predictions_and_attributes_identical(self, model, saved):
        loaded = SpectralModel.load(saved)
        samples = SMALL.draw(50, seed=21)
        np.testing.assert_array_equal(loaded.predict(samples), model.predict(samples))
        for name in (
            "wavelengths_",
            "mean_",
            "components_",
            "explained_variance_ratio_",
            "scale_center_",
            "scale_halfwidth_",
            "powers_",
            "W_",
        ):
            np.testing.assert_array_equal(getattr(loaded, name), getattr(model, name))
        assert loaded.get_params() == model.get_params()
        assert loaded.domain_ == model.domain_
        assert (loaded.parameter_names_, loaded.forms_, loaded.n_components_) == (
            model.parameter_names_,
            model.forms_,
            model.n_components_,
        )
        assert loaded.training_set_ == {"path": "somewhere/dataset.nc", "seed": 3}
        assert loaded.holdout_scores_ == {"rms_error_overall": 0.001}
        assert loaded.training_rms_ == model.training_rms_

    def test_plain_arrays_and_readable_metadata(self, saved):
        with np.load(saved, allow_pickle=False) as npz:  # no object arrays anywhere
            assert {npz[k].dtype.kind for k in npz.files} <= {"f", "i", "U"}
            meta = json.loads(str(npz["metadata"][()]))
        assert meta["format"] == "sandlight-spectral-model" and meta["format_version"] == 2
        assert meta["sandlight_version"] == sandlight.__version__
        assert meta["parameter_names"] == list(SMALL.names)
        assert meta["domain"]["fixed"]["depth_mm"] == float("inf")
        iron = meta["domain"]["dimensions"][SMALL.names.index("iron_oxide")]
        assert (iron["scale"], iron["offset"]) == ("log", 1e-4)
        assert (meta["name"], meta["description"]) == ("small", "a test model")

    def test_save_is_deterministic_and_atomic(self, model, saved, tmp_path):
        again = model.save(tmp_path / "again.npz")
        assert again.read_bytes() == saved.read_bytes()
        assert sorted(p.name for p in tmp_path.iterdir()) == ["again.npz", "model.npz"]


class TestRefused:
    def test_missing(self, tmp_path):
        with pytest.raises(ModelFileError, match="does not exist"):
            SpectralModel.load(tmp_path / "nope.npz")

    @pytest.mark.parametrize("keep", [0.3, 0.9, 0.999])
    def test_truncated(self, saved, keep):
        data = saved.read_bytes()
        saved.write_bytes(data[: int(len(data) * keep)])
        with pytest.raises(ModelFileError, match="not a readable"):
            SpectralModel.load(saved)

    def test_flipped_byte(self, saved):
        data = bytearray(saved.read_bytes())
        with zipfile.ZipFile(saved) as z:  # a byte in the middle of the coefficients' data
            info = z.getinfo("W.npy")
        # local file header: 30 bytes, then the file name and the extra field (lengths at 26, 28)
        start = (
            info.header_offset
            + 30
            + int.from_bytes(data[info.header_offset + 26 : info.header_offset + 28], "little")
            + int.from_bytes(data[info.header_offset + 28 : info.header_offset + 30], "little")
        )
        data[start + info.file_size // 2] ^= 0xFF
        saved.write_bytes(bytes(data))
        with pytest.raises(ModelFileError, match="CRC"):
            SpectralModel.load(saved)

    def test_not_a_zip(self, tmp_path):
        path = tmp_path / "model.npz"
        path.write_text("format = 'sandlight-spectral-model'\n")
        with pytest.raises(ModelFileError, match="not a readable"):
            SpectralModel.load(path)

    def test_foreign_npz(self, tmp_path):
        path = tmp_path / "other.npz"
        np.savez(path, weights=np.ones(3))
        with pytest.raises(ModelFileError, match="without a metadata entry"):
            SpectralModel.load(path)

    def test_pickled_npz(self, tmp_path):
        path = tmp_path / "pickled.npz"
        np.savez(path, metadata=np.array([{"format": "sandlight-spectral-model"}], dtype=object))
        with pytest.raises(ModelFileError):
            SpectralModel.load(path)

    def test_other_format(self, saved, tmp_path):
        path = with_metadata(saved, tmp_path / "x.npz", format="sandlight-brdf-model")
        with pytest.raises(ModelFileError, match="sandlight-brdf-model"):
            SpectralModel.load(path)

    def test_newer_format_version(self, saved, tmp_path):
        path = with_metadata(saved, tmp_path / "x.npz", format_version=3)
        with pytest.raises(ModelFileError, match="format version 3.*upgrade"):
            SpectralModel.load(path)

    def test_inconsistent_shapes(self, saved, tmp_path):
        path = rewrite(saved, tmp_path / "x.npz", lambda k, a: a[:, :, :-1] if k == "W" else a)
        with pytest.raises(ModelFileError, match="'W' has shape"):
            SpectralModel.load(path)

    def test_missing_array(self, saved, tmp_path):
        path = rewrite(saved, tmp_path / "x.npz", lambda k, a: None if k == "mean" else a)
        with pytest.raises(ModelFileError, match="missing arrays.*mean"):
            SpectralModel.load(path)

    def test_scaling_that_contradicts_the_domain(self, saved, tmp_path):
        path = rewrite(saved, tmp_path / "x.npz", lambda k, a: a * 1.01 if k == "scale_halfwidth" else a)
        with pytest.raises(ModelFileError, match="scaling"):
            SpectralModel.load(path)

    def test_nan_coefficients(self, saved, tmp_path):
        path = rewrite(saved, tmp_path / "x.npz", lambda k, a: np.full_like(a, np.nan) if k == "mean" else a)
        with pytest.raises(ModelFileError, match="NaN"):
            SpectralModel.load(path)


def test_other_sandlight_version_warns(model, saved, tmp_path):
    path = with_metadata(saved, tmp_path / "x.npz", sandlight_version="0.0.1")
    with pytest.warns(ModelVersionWarning, match="sandlight 0.0.1"):
        loaded = SpectralModel.load(path)
    samples = SMALL.draw(5, seed=1)
    np.testing.assert_array_equal(loaded.predict(samples), model.predict(samples))


def test_format_1_file_still_loads(tmp_path):
    """Format 1 had √c-scaled concentrations, no log offsets and no model name: such a file
    reads back with the same predictions, named after the file."""
    iron = SMALL.dimension("iron_oxide")
    dims = tuple(
        Dimension("iron_oxide", iron.low, iron.high, "sqrt") if d.name == "iron_oxide" else d for d in SMALL.dimensions
    )
    domain = Domain(dims, SMALL.forms, SMALL.fixed, SMALL.texture_limit)
    train, R, _, _ = exact_cubic_problem(domain, 300, seed=3)
    model = SpectralModel(ridge=1e-9).fit(train, R, wavelengths_nm=WL, domain=domain)
    saved = model.save(tmp_path / "new.npz")

    def as_format_1(name, array):
        if name != "metadata":
            return array
        meta = json.loads(str(array[()]))
        meta["format_version"] = 1
        del meta["name"], meta["description"]
        for d in meta["domain"]["dimensions"]:
            del d["offset"]
        return np.array(json.dumps(meta))

    old = rewrite(saved, tmp_path / "spectral-old.npz", as_format_1)
    loaded = SpectralModel.load(old)
    assert loaded.name_ == "spectral-old" and loaded.domain_ == domain
    samples = domain.draw(20, seed=4)
    np.testing.assert_array_equal(loaded.predict(samples), model.predict(samples))


class TestDefaultModel:
    def test_absent_default_model_is_a_clear_error(self, monkeypatch, tmp_path):
        monkeypatch.setattr(bank, "default_model_dir", lambda: tmp_path)
        default_model.cache_clear()
        with pytest.raises(SandlightError, match="no spectral model is installed"):
            default_model()

    def test_present_default_models_are_loaded_once(self, monkeypatch, saved, model, tmp_path):
        models = tmp_path / "models"
        models.mkdir()
        saved.rename(models / "spectral-small.npz")
        monkeypatch.setattr(bank, "default_model_dir", lambda: models)
        default_model.cache_clear()
        try:
            first = default_model()
            assert default_model() is first
            assert [m.name_ for m in first.models] == ["small"]
            samples = SMALL.draw(3, seed=2)
            np.testing.assert_array_equal(first.predict(samples), model.predict(samples))
        finally:
            default_model.cache_clear()
