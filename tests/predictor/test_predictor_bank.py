"""Model bank: each sample is predicted by the most accurate model whose domain contains it."""

import numpy as np
import pytest
from test_predictor_spectral import SMALL, WL, exact_cubic_problem

from sandlight.errors import ParameterError
from sandlight.predictor import Dimension, Domain, ModelBank, SpectralModel

#: A narrow domain inside SMALL: saturation fixed at 0, iron oxide from 0.001 to 0.05.
NARROW = SMALL.restrict(saturation=0.0, iron_oxide=(0.001, 0.05))


def fitted(domain, name, error, seed):
    train, R, _, _ = exact_cubic_problem(domain, 300, seed=seed)
    model = SpectralModel(ridge=1e-9).fit(
        train, R, wavelengths_nm=WL, domain=domain, name=name, description=f"test model {name}"
    )
    model.holdout_scores_ = {"rms_error_overall": error, "n_samples": 10}
    return model


@pytest.fixture(scope="module")
def models():
    # Same random polynomial of the *scaled* parameters, but the domains scale differently:
    # the two models disagree everywhere (checked below), so the routing is visible.
    return fitted(SMALL, "broad", 0.05, seed=1), fitted(NARROW, "narrow", 0.002, seed=2)


@pytest.fixture(scope="module")
def bank(models):
    return ModelBank(models)


def samples_of(domain, n, seed):
    return domain.draw(n, seed=seed, design="random")


class TestSelection:
    def test_ranked_by_holdout_error(self, bank):
        assert [m.name_ for m in bank.models] == ["narrow", "broad"]
        assert "narrow" in bank.describe(0) and "0.0020" in bank.describe("narrow")

    def test_each_sample_goes_to_the_best_covering_model(self, bank, models):
        broad, narrow = models
        inside = samples_of(NARROW, 20, seed=5)
        outside = samples_of(SMALL, 200, seed=6)
        outside = [s for s in outside if s["saturation"] > 0][:20]
        mixed = [x for pair in zip(inside, outside) for x in pair]  # interleaved
        r, used = bank.predict(mixed, return_models=True)
        assert list(used) == ["narrow", "broad"] * 20
        np.testing.assert_array_equal(r[0::2], narrow.predict(inside))
        np.testing.assert_array_equal(r[1::2], broad.predict(outside))
        np.testing.assert_array_equal(bank.select(mixed), [0, 1] * 20)
        assert np.abs(broad.predict(inside) - narrow.predict(inside)).min() > 1e-6

    def test_a_fixed_parameter_of_another_value_is_not_covered(self, bank):
        sample = samples_of(NARROW, 1, seed=7)[0]
        assert bank.select([{**sample, "saturation": 0.3}])[0] == 1  # broad
        assert bank.select([{**sample, "saturation": 0.0}])[0] == 0  # narrow

    def test_a_missing_parameter_takes_the_sandsample_default(self, bank):
        full = samples_of(NARROW, 1, seed=7)[0]
        # depth_mm: the default (inf) is the value both models are fixed at.
        sample = {k: v for k, v in full.items() if k != "depth_mm"}
        assert bank.select([sample])[0] == bank.select([full])[0] == 0
        np.testing.assert_array_equal(bank.predict([sample]), bank.predict([full]))
        # coating_iron_share: the default (0.2) is not the 0.5 both models are fixed at.
        sample = {k: v for k, v in full.items() if k != "coating_iron_share"}
        assert bank.select([sample])[0] == -1
        with pytest.raises(ParameterError, match=r"coating_iron_share = 0\.2.*no model of the bank"):
            bank.predict([sample])


class TestOutsideEveryDomain:
    def test_refused_naming_the_parameter(self, bank):
        sample = {**samples_of(SMALL, 1, seed=8)[0], "grain_size": 3.0}
        with pytest.raises(ParameterError, match=r"grain_size = 3\.0.*no model of the bank"):
            bank.predict([sample])

    def test_extrapolate_uses_the_broadest_model(self, bank, models):
        sample = {**samples_of(SMALL, 1, seed=8)[0], "grain_size": 3.0}
        r, used = bank.predict([sample], extrapolate=True, return_models=True)
        assert list(used) == ["broad"]
        np.testing.assert_array_equal(r, models[0].predict([sample], extrapolate=True))

    def test_extrapolation_takes_the_model_of_the_samples_water_regime(self):
        # Broad models split by water, and a less accurate one over both (as shipped): a dry
        # sample out of range in grain size is extrapolated by the dry model, not by the wet one
        # nor by the one over both (as near: out in grain size only, but less accurate).
        dry = fitted(SMALL.restrict(saturation=0.0), "dry", 0.01, seed=3)
        wet = fitted(SMALL.restrict(saturation=(0.001, 1.0)), "wet", 0.02, seed=4)
        both = fitted(SMALL, "both", 0.05, seed=5)
        two = ModelBank([dry, wet, both])
        base = samples_of(SMALL, 1, seed=8)[0]
        samples = [{**base, "grain_size": 3.0, "saturation": s} for s in (0.0, 0.5)]
        r, used = two.predict(samples, extrapolate=True, return_models=True)
        assert list(used) == ["dry", "wet"]
        np.testing.assert_array_equal(r[0], dry.predict(samples[:1], extrapolate=True)[0])
        np.testing.assert_array_equal(r[1], wet.predict(samples[1:], extrapolate=True)[0])
        # Refused naming the parameter really out of range, not the water of the other regime.
        with pytest.raises(ParameterError, match=r"grain_size = 3\.0.*'dry', the nearest"):
            two.predict(samples[:1])

    def test_form_of_no_model(self, bank):
        sample = {**samples_of(NARROW, 1, seed=9)[0], "iron_oxide_form": "mixed"}
        with pytest.raises(ParameterError, match="mixed"):
            bank.predict([sample])


class TestInputs:
    def test_plain_arrays_are_ambiguous(self, bank):
        with pytest.raises(ParameterError, match="named parameters"):
            bank.predict(np.zeros((2, len(SMALL.names))))

    def test_a_missing_form_is_the_default_coating(self, bank):
        sample = samples_of(NARROW, 1, seed=10)[0]
        del sample["iron_oxide_form"]
        np.testing.assert_array_equal(bank.predict([sample]), bank.predict([{**sample, "iron_oxide_form": "coating"}]))

    def test_models_must_share_wavelengths_and_names(self, models):
        broad, narrow = models
        other = SpectralModel(ridge=1e-9).fit(
            *exact_cubic_problem(NARROW, 300, seed=2)[:2], wavelengths_nm=WL + 1, domain=NARROW, name="x"
        )
        with pytest.raises(ParameterError, match="wavelengths"):
            ModelBank([broad, other])
        with pytest.raises(ParameterError, match="distinct names"):
            ModelBank([broad, broad])
        with pytest.raises(ParameterError, match="at least one"):
            ModelBank([])

    def test_models_must_share_the_engine_memory(self, models):
        broad, narrow = models
        assert ModelBank(models).memory_ == "none"
        train, R, _, _ = exact_cubic_problem(NARROW, 300, seed=2)
        packed = SpectralModel(ridge=1e-9).fit(
            train, R, wavelengths_nm=WL, domain=NARROW, name="packed", training_set={"engine": {"memory": "packed"}}
        )
        assert packed.memory_ == "packed"
        with pytest.raises(ParameterError, match="engine memory.*'broad': 'none'.*'packed': 'packed'"):
            ModelBank([broad, packed])

    def test_save_load_keeps_name_and_rank(self, models, tmp_path):
        paths = [m.save(tmp_path / f"spectral-{m.name_}.npz") for m in models]
        loaded = ModelBank.load(paths)
        assert [m.name_ for m in loaded.models] == ["narrow", "broad"]
        assert loaded.models[0].description_ == "test model narrow"


class TestDomainContains:
    def test_agrees_with_check(self):
        values, codes = SMALL.draw_arrays(200, seed=11, design="random")
        values[::3, SMALL.names.index("grain_size")] = 2.5  # outside
        columns = {n: values[:, j] for j, n in enumerate(SMALL.names)}
        columns.update({k: np.full(200, v) for k, v in SMALL.fixed.items()})
        forms = np.array(SMALL.forms)[codes]
        inside = SMALL.contains(columns, forms)
        assert inside.sum() == 200 - len(range(0, 200, 3))
        for row in range(10):
            if inside[row]:
                SMALL.check(values[row : row + 1])
            else:
                with pytest.raises(ParameterError):
                    SMALL.check(values[row : row + 1])

    def test_texture_class_and_nan(self):
        domain = Domain.default()
        values, codes = domain.draw_arrays(2, seed=12)
        columns = {n: values[:, j].copy() for j, n in enumerate(domain.names)}
        columns["depth_mm"] = np.full(2, np.inf)
        columns["host_absorption"] = np.ones(2)
        columns["host_scattering"] = np.zeros(2)
        columns["coating_coverage"] = np.ones(2)
        columns["silt"][0], columns["clay"][0] = 0.09, 0.05  # 0.09 + 1.5·0.05 = 0.165 > 0.15
        columns["porosity"][1] = np.nan
        assert not domain.contains(columns, np.array(domain.forms)[codes]).any()


def test_reference_domain_fixes_the_reference_sand():
    from sandlight.predictor.domain import REFERENCE_SAND

    domain = Domain.reference(
        [Dimension("iron_oxide", 0.001, 0.05, "log"), Dimension("saturation", 0.0, 1.0)], forms=["coating"]
    )
    assert domain.names == ("iron_oxide", "saturation")
    assert domain.fixed == {k: v for k, v in REFERENCE_SAND.items() if k not in ("iron_oxide", "saturation")}
    sample = domain.draw(1, seed=1)[0]
    assert sample["sand"] == pytest.approx(1 - REFERENCE_SAND["silt"] - REFERENCE_SAND["clay"])


def test_reference_sand_is_sandsample_default():
    sample_module = pytest.importorskip("sandlight.sample")
    from sandlight.predictor.domain import REFERENCE_SAND

    defaults = sample_module.SandSample()
    assert {k: float(getattr(defaults, k)) for k in REFERENCE_SAND} == REFERENCE_SAND
