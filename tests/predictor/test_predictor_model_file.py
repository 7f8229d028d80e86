"""Model files: save → load → identical predictions; damaged or foreign files refused."""

import io
import json
import os
import zipfile

import numpy as np
import pytest
import xarray as xr
from test_predictor_spectral import SMALL, WL, exact_cubic_problem

import sandlight
import sandlight.predictor.bank as bank
from sandlight.errors import ModelFileError, SandlightError
from sandlight.predictor import Dimension, Domain, ModelVersionWarning, SpectralModel, default_model
from sandlight.predictor.model_file import MAX_ARRAY_BYTES, MAX_JSON_DEPTH, json_depth
from sandlight.spatial import SpatialModel


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
        assert meta["format"] == "sandlight-spectral-model" and meta["format_version"] == 4
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
        path = with_metadata(saved, tmp_path / "x.npz", format_version=5)
        with pytest.raises(ModelFileError, match="format version 5.*upgrade"):
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


def repack(src, dst, add=None, declared=None):
    """Copy a model file member by member (plain zipfile, no zip64), adding members ``add``
    (name → bytes) and making the central directory declare ``declared`` (name → uncompressed
    size) for the members named."""
    with zipfile.ZipFile(src) as z:
        members = {i.filename: z.read(i) for i in z.infolist()}
    members.update(add or {})
    with zipfile.ZipFile(dst, "w") as z:
        for name, data in members.items():
            z.writestr(name, data)
    raw = bytearray(dst.read_bytes())
    for name, size in (declared or {}).items():
        # central directory entry: signature PK\1\2, uncompressed size at 24, name at 46
        entry = raw.index(b"PK\x01\x02")
        while bytes(raw[entry + 46 : entry + 46 + len(name)]) != name.encode():
            entry = raw.index(b"PK\x01\x02", entry + 4)
        raw[entry + 24 : entry + 28] = size.to_bytes(4, "little")
    dst.write_bytes(bytes(raw))
    return dst


def npy_bytes(array):
    buffer = io.BytesIO()
    np.save(buffer, array)
    return buffer.getvalue()


@pytest.fixture
def opened(monkeypatch):
    """Names of the zip members read (zipfile.ZipFile.open calls) during a test."""
    names = []
    original = zipfile.ZipFile.open

    def spy(self, name, *args, **kwargs):
        names.append(name.filename if isinstance(name, zipfile.ZipInfo) else name)
        return original(self, name, *args, **kwargs)

    monkeypatch.setattr(zipfile.ZipFile, "open", spy)
    return names


class TestUntrustedFiles:
    """Issue 24 #8 and #15: the zip directory and the headers are checked before anything is read,
    and a file that is not a model file is called what it is not."""

    def test_unknown_member_refused_before_reading_anything(self, saved, tmp_path, opened):
        path = repack(saved, tmp_path / "x.npz", add={"payload.npy": npy_bytes(np.zeros(1000))})
        opened.clear()
        with pytest.raises(ModelFileError, match=r"members \['payload.npy'\] that a spectral model file does not"):
            SpectralModel.load(path)
        assert opened == []

    def test_oversize_member_refused_before_reading_anything(self, saved, tmp_path, opened):
        # A 3 GB member, as the central directory declares it (the file itself stays small).
        path = repack(saved, tmp_path / "x.npz", declared={"W.npy": 3_000_000_000})
        opened.clear()
        with pytest.raises(ModelFileError, match=f"W.npy declares 3000000000 bytes, more than the {MAX_ARRAY_BYTES}"):
            SpectralModel.load(path)
        assert opened == []

    def test_array_header_larger_than_the_member_is_refused(self, saved, tmp_path):
        # An .npy header announcing 10⁹ doubles before the 8 bytes the member holds: refused from
        # the header, before numpy would allocate 8 GB for it.
        buffer = io.BytesIO()
        np.lib.format.write_array_header_1_0(buffer, {"descr": "<f8", "fortran_order": False, "shape": (10**9,)})
        path = repack(saved, tmp_path / "x.npz", add={"W.npy": buffer.getvalue() + bytes(8)})
        with pytest.raises(ModelFileError, match=r"W.npy declares an array of \(1000000000,\) float64"):
            SpectralModel.load(path)

    def test_deeply_nested_metadata_is_refused_without_recursion(self, tmp_path):
        path = tmp_path / "deep.npz"
        np.savez(path, metadata=np.array("[" * 100_000 + "]" * 100_000))
        with pytest.raises(ModelFileError, match=f"nested 100000 levels deep.*at most {MAX_JSON_DEPTH}"):
            SpectralModel.load(path)

    def test_nesting_within_the_limit_loads(self, saved, tmp_path, model):
        deep = [[[[[[[[[[{"x": "]]]] brackets in strings do not count [[[["}]]]]]]]]]]
        path = with_metadata(saved, tmp_path / "x.npz", training_set={"nested": deep})
        np.testing.assert_array_equal(SpectralModel.load(path).W_, model.W_)

    def test_json_depth(self):
        assert [json_depth(t) for t in ("1", "[]", '{"a": [1, {"b": []}]}', '["[[[", "\\"]"]')] == [0, 1, 4, 1]

    @pytest.mark.parametrize("load", [SpectralModel.load, SpatialModel.load], ids=["spectral", "spatial"])
    @pytest.mark.parametrize(
        "content, what",
        [
            (os.urandom(4096), "not a zip"),
            ("netcdf", "not a zip.*NetCDF"),
            (npy_bytes(np.ones(3)), "not a zip.*single numpy array"),
        ],
        ids=["random-bytes", "netcdf", "npy"],
    )
    def test_not_a_model_file_says_what_it_is_not(self, tmp_path, load, content, what):
        path = tmp_path / "model.npz"
        if content == "netcdf":
            xr.Dataset({"reflectance": ("wavelength", np.ones(3))}).to_netcdf(path)
        else:
            path.write_bytes(content)
        with pytest.raises(ModelFileError, match=what) as info:
            load(path)
        assert "allow_pickle" not in str(info.value)

    @pytest.mark.parametrize("load", [SpectralModel.load, SpatialModel.load], ids=["spectral", "spatial"])
    def test_pickled_member_is_refused_without_inviting_to_unpickle(self, tmp_path, load):
        path = tmp_path / "pickled.npz"
        np.savez(path, metadata=np.array([{"format": "sandlight-spectral-model"}], dtype=object))
        with pytest.raises(ModelFileError, match="holds Python objects") as info:
            load(path)
        assert "allow_pickle" not in str(info.value)

    def test_a_directory_is_not_a_model_file(self, tmp_path):
        with pytest.raises(ModelFileError, match="not a regular file"):
            SpectralModel.load(tmp_path)


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
        bank.shipped_banks.cache_clear()
        with pytest.raises(SandlightError, match="no spectral model is installed"):
            default_model()

    def test_present_default_models_are_loaded_once(self, monkeypatch, saved, model, tmp_path):
        models = tmp_path / "models"
        models.mkdir()
        saved.rename(models / "spectral-small.npz")
        monkeypatch.setattr(bank, "default_model_dir", lambda: models)
        bank.shipped_banks.cache_clear()
        try:
            first = default_model()
            assert default_model() is first
            assert [m.name_ for m in first.models] == ["small"]
            samples = SMALL.draw(3, seed=2)
            np.testing.assert_array_equal(first.predict(samples), model.predict(samples))
        finally:
            bank.shipped_banks.cache_clear()

    def test_models_on_other_grids_form_their_own_bank(self, monkeypatch, saved, tmp_path):
        # The paper's bank and the full-range bank ship side by side: one bank per grid, the
        # paper's found by its 400-700 nm span, the full range by the widest span.
        models = tmp_path / "models"
        models.mkdir()
        saved.rename(models / "spectral-small.npz")
        _wide_model().save(models / "spectral-wide.npz")
        monkeypatch.setattr(bank, "default_model_dir", lambda: models)
        bank.shipped_banks.cache_clear()
        try:
            assert [b.wavelengths_.size for b in bank.shipped_banks()] == [WL.size, WIDE_WL.size]
            assert [m.name_ for m in default_model().models] == ["small"]
            assert [m.name_ for m in bank.full_range_model().models] == ["wide"]
        finally:
            bank.shipped_banks.cache_clear()

    def test_no_shipped_model_on_the_papers_grid_is_a_clear_error(self, monkeypatch, tmp_path):
        models = tmp_path / "models"
        models.mkdir()
        _wide_model().save(models / "spectral-wide.npz")
        monkeypatch.setattr(bank, "default_model_dir", lambda: models)
        bank.shipped_banks.cache_clear()
        try:
            with pytest.raises(ModelFileError, match="no shipped spectral model spans 400–700 nm"):
                default_model()
        finally:
            bank.shipped_banks.cache_clear()


WIDE_WL = np.arange(350.0, 2501.0, 50.0)


def _wide_model():
    """A model on a grid other than the paper's (only its grid matters here)."""
    train = SMALL.draw(60, seed=5)
    scale = np.random.default_rng(5).uniform(0.8, 1.0, (len(train), 1))
    values = scale * np.linspace(0.2, 0.8, WIDE_WL.size)
    return SpectralModel(ridge=1e-9).fit(train, values, wavelengths_nm=WIDE_WL, domain=SMALL, name="wide")
