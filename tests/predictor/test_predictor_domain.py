"""Training domains: draws inside the domain, Latin hypercube strata, scales, checks."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from sandlight.errors import ParameterError, SandlightError
from sandlight.predictor import Dimension, Domain
from sandlight.predictor.domain import FORMS

DEFAULT = Domain.default()


def column(samples, name):
    return np.array([s[name] for s in samples])


@pytest.fixture(scope="module")
def draws():
    return DEFAULT.draw(3000, seed=1)


class TestDraw:
    def test_deterministic(self, draws):
        assert DEFAULT.draw(3000, seed=1) == draws
        assert DEFAULT.draw(3000, seed=2) != draws

    def test_every_parameter_inside_its_range(self, draws):
        for d in DEFAULT.dimensions:
            values = column(draws, d.name)
            assert values.min() >= d.low and values.max() <= d.high, d.name
            if d.name in ("silt", "clay"):
                continue  # their maxima are corners of the class triangle (tested below)
            # the draws reach close to both ends of every range
            assert d.forward(values.min()) - d.forward(d.low) < 0.01 * (d.forward(d.high) - d.forward(d.low)), d.name
            assert d.forward(d.high) - d.forward(values.max()) < 0.01 * (d.forward(d.high) - d.forward(d.low)), d.name

    def test_texture_inside_the_sand_class(self, draws):
        silt, clay, sand = (column(draws, n) for n in ("silt", "clay", "sand"))
        np.testing.assert_allclose(sand + silt + clay, 1.0, rtol=0, atol=1e-15)
        assert (silt + 1.5 * clay <= 0.15 + 1e-15).all() and (sand >= 0.85).all()
        assert (silt >= 0).all() and (clay >= 0).all()
        # class fill and silt share are uniform draws: their means are 1/2
        fill = (silt + 1.5 * clay) / 0.15
        share = silt / (silt + clay)
        assert abs(fill.mean() - 0.5) < 0.02 and abs(share.mean() - 0.5) < 0.02

    def test_fixed_and_forms(self, draws):
        assert all(
            s["depth_mm"] == math.inf
            and s["host_absorption"] == 1.0
            and s["host_scattering"] == 0.0
            and s["coating_coverage"] == 1.0
            for s in draws
        )
        forms = column(draws, "iron_oxide_form")
        assert {f: int((forms == f).sum()) for f in FORMS} == {f: 1000 for f in FORMS}
        assert set(draws[0]) == set(DEFAULT.names) | {
            "sand",
            "depth_mm",
            "host_absorption",
            "host_scattering",
            "coating_coverage",
            "iron_oxide_form",
        }

    def test_latin_hypercube_strata_per_form(self, draws):
        # Within each form, every dimension's draw coordinate hits each of the n strata once.
        forms = column(draws, "iron_oxide_form")
        for name in ("porosity", "grain_size", "iron_oxide"):
            d = DEFAULT.dimension(name)
            for f in FORMS:
                t = d.forward(column(draws, name)[forms == f])
                u = (t - d.forward(d.low)) / (d.forward(d.high) - d.forward(d.low))
                strata = np.floor(u * len(u) * (1 - 1e-12)).astype(int)
                assert sorted(strata) == list(range(len(u))), (name, f)

    def test_scales(self, draws):
        # log scale with offset c₀ = 1e-4: uniform in ln(c + c₀) over [0, 0.1], so the median is
        # √(c₀·(0.1 + c₀)) − c₀ ≈ 3.06e-3 and a third of the draws lie below 1e-3
        # ((ln(1.1e-3) − ln(1e-4))/(ln(0.1001) − ln(1e-4)) = 0.347);
        # log scale: the median of grain_size is the geometric mean √(0.05·2) ≈ 0.316 mm.
        iron = column(draws, "iron_oxide")
        assert np.median(iron) == pytest.approx(math.sqrt(1e-4 * 0.1001) - 1e-4, rel=0.05)
        assert np.mean(iron < 1e-3) == pytest.approx(0.347, abs=0.02)
        assert iron.min() >= 0.0
        assert np.median(column(draws, "grain_size")) == pytest.approx(math.sqrt(0.1), rel=0.05)
        assert np.median(column(draws, "porosity")) == pytest.approx(0.40, rel=0.02)

    def test_arrays_and_dicts_agree(self, draws):
        values, codes = DEFAULT.draw_arrays(3000, seed=1)
        np.testing.assert_array_equal(values, [[s[n] for n in DEFAULT.names] for s in draws])
        assert [DEFAULT.forms[c] for c in codes] == list(column(draws, "iron_oxide_form"))

    def test_random_design(self):
        draws = DEFAULT.draw(600, seed=5, design="random")
        counts = [int((column(draws, "iron_oxide_form") == f).sum()) for f in FORMS]
        assert sum(counts) == 600 and min(counts) > 150
        DEFAULT.check(np.array([[s[n] for n in DEFAULT.names] for s in draws]))

    def test_bad_arguments(self):
        with pytest.raises(ParameterError, match="design"):
            DEFAULT.draw(10, seed=1, design="sobol")
        with pytest.raises(ParameterError, match="n = 0"):
            DEFAULT.draw(0, seed=1)


class TestRestrictAndSerialise:
    def test_restrict(self):
        d = DEFAULT.restrict(forms=["coating"], saturation=0.0, iron_oxide=(0.0, 0.02), texture_limit=0.06)
        assert "saturation" not in d.names and d.fixed["saturation"] == 0.0
        assert d.dimension("iron_oxide").high == 0.02 and d.forms == ("coating",)
        assert d.dimension("silt").high == 0.06 and d.dimension("clay").high == pytest.approx(0.04)
        draws = d.draw(200, seed=3)
        assert all(s["silt"] + 1.5 * s["clay"] <= 0.06 + 1e-15 for s in draws)
        assert all(s["saturation"] == 0.0 and s["iron_oxide"] <= 0.02 for s in draws)

    def test_fixed_texture(self):
        d = DEFAULT.restrict(silt=0.05, clay=0.02)
        s = d.draw(3, seed=1)[0]
        assert (s["silt"], s["clay"], s["sand"]) == (0.05, 0.02, pytest.approx(0.93))

    @pytest.mark.parametrize(
        "kwargs, name",
        [
            ({"porosity": (0.2, 0.5)}, "porosity"),
            ({"porosity": 0.7}, "porosity"),
            ({"silt": (0.0, 0.1)}, "silt"),
            ({"silt": 0.05}, "silt, clay"),
            ({"colour": 1.0}, "colour"),
            ({"forms": ["hematite"]}, "forms"),
            ({"texture_limit": 0.2}, "texture_limit"),
        ],
    )
    def test_bad_restrictions(self, kwargs, name):
        with pytest.raises(ParameterError) as info:
            DEFAULT.restrict(**kwargs)
        assert info.value.name == name

    def test_fixed_texture_outside_the_class(self):
        with pytest.raises(ParameterError, match="silt"):
            DEFAULT.restrict(silt=0.1, clay=0.05)

    def test_round_trip(self):
        d = DEFAULT.restrict(forms=["mixed", "particles"], porosity=(0.3, 0.4), magnetite=0.0)
        assert Domain.from_dict(d.to_dict()) == d

    def test_a_stored_domain_fixes_a_parameter_added_after_it_at_its_default(self):
        # Models trained before host_absorption, host_scattering and coating_coverage existed
        # store fixed = {depth_mm: inf} only.
        stored = DEFAULT.to_dict()
        for name in ("host_absorption", "host_scattering", "coating_coverage"):
            del stored["fixed"][name]
        loaded = Domain.from_dict(stored)
        assert loaded.fixed == {
            "depth_mm": math.inf,
            "host_absorption": 1.0,
            "host_scattering": 0.0,
            "coating_coverage": 1.0,
        }
        columns = {n: np.full(4, 0.5 * (d.low + d.high)) for n, d in zip(DEFAULT.names, DEFAULT.dimensions)}
        columns.update(
            depth_mm=np.full(4, math.inf),
            host_absorption=np.array([1.0, 2.0, 1.0, 1.0]),
            host_scattering=np.array([0.0, 0.0, 0.0, 3.0]),
            coating_coverage=np.array([1.0, 1.0, 0.5, 1.0]),
        )
        assert loaded.contains(columns).tolist() == [True, False, False, False]

    def test_bad_dimensions(self):
        with pytest.raises(ParameterError, match="low > 0"):
            Dimension("grain_size", 0.0, 2.0, "log")
        with pytest.raises(ParameterError, match="scale"):
            Dimension("grain_size", 0.1, 2.0, "cubic")


class TestCheck:
    def test_values_inside_pass_and_outside_fail(self):
        X = np.array([[DEFAULT.dimension(n).low for n in DEFAULT.names]])
        DEFAULT.check(X)
        X[0, DEFAULT.names.index("porosity")] = 0.56
        with pytest.raises(ParameterError, match=r"porosity = 0.56 .*\[0.25, 0.55\]"):
            DEFAULT.check(X)
        DEFAULT.check(X, extrapolate=True)

    def test_scaled_maps_ranges_to_unit_interval(self):
        lo = np.array([[d.low for d in DEFAULT.dimensions]])
        hi = np.array([[d.high for d in DEFAULT.dimensions]])
        np.testing.assert_allclose(DEFAULT.scaled(lo), -1.0, atol=1e-14)
        np.testing.assert_allclose(DEFAULT.scaled(hi), 1.0, atol=1e-14)
        mid = np.array(
            [
                [
                    math.sqrt(0.05 * 2)
                    if n == "grain_size"
                    # midpoint of ln(c + 1e-4) over [0, 0.1]: √(1e-4·0.1001) − 1e-4
                    else (math.sqrt(1e-4 * 0.1001) - 1e-4 if n == "iron_oxide" else 0.5 * (d.low + d.high))
                    for n, d in zip(DEFAULT.names, DEFAULT.dimensions)
                ]
            ]
        )
        for n in ("grain_size", "iron_oxide", "porosity"):
            assert DEFAULT.scaled(mid)[0, DEFAULT.names.index(n)] == pytest.approx(0.0, abs=1e-12)


class TestContains:
    NARROW = Domain.reference([Dimension("iron_oxide", 0.001, 0.05, "log")])

    def columns(self, **overrides):
        row = {**self.NARROW.fixed, "iron_oxide": 0.01, **overrides}
        return {k: np.array([v]) for k, v in row.items()}

    def test_reference_sand_is_inside(self):
        assert self.NARROW.fixed["depth_mm"] == math.inf
        assert self.NARROW.contains(self.columns()).all()

    def test_finite_depth_is_not_the_semi_infinite_reference(self):
        # |5 − inf| ≤ 1e-9·inf holds: a relative tolerance alone would claim depth_mm = 5 covered.
        assert not self.NARROW.contains(self.columns(depth_mm=5.0)).any()

    def test_fixed_value_tolerates_text_round_off_only(self):
        g = self.NARROW.fixed["grain_size"]
        assert self.NARROW.contains(self.columns(grain_size=g * (1 + 1e-12))).all()
        assert not self.NARROW.contains(self.columns(grain_size=g * (1 + 1e-6))).any()
        assert not self.NARROW.contains(self.columns(grain_size=math.nan)).any()


class TestCoversSampleParameters:
    def fake_parameters(self, **overrides):
        rows = [SimpleNamespace(name=d.name, low=d.low, high=d.high, kind="float") for d in DEFAULT.dimensions]
        rows += [
            SimpleNamespace(name="sand", low=0.85, high=1.0, kind="float"),
            SimpleNamespace(name="depth_mm", low=0.0, high=math.inf, kind="float"),
            SimpleNamespace(name="iron_oxide_form", kind="choice", choices=FORMS),
        ]
        return rows + [SimpleNamespace(**o) for o in overrides.values()]

    def test_default_domain_covers_the_documented_parameters(self):
        DEFAULT.check_covers(self.fake_parameters())

    def test_unknown_parameter_is_reported(self):
        params = self.fake_parameters(goethite={"name": "goethite", "low": 0.0, "high": 0.1, "kind": "float"})
        with pytest.raises(SandlightError, match="goethite"):
            DEFAULT.check_covers(params)

    def test_real_sample_module(self):
        sample = pytest.importorskip("sandlight.sample")
        DEFAULT.check_covers(sample.PARAMETERS)
        for s in DEFAULT.draw(30, seed=4):
            sample.SandSample(**s)  # every draw is a valid sample


def test_every_default_domain_draw_is_a_physical_sample():
    # The training domain must never hand the engine a sample the mass balance refuses.
    from sandlight.physics.composition import compose
    from sandlight.predictor.domain import Domain
    from sandlight.sample import SandSample

    for params in Domain.default().draw(3000, seed=3, design="random"):
        comp = compose(SandSample(**params))
        assert comp.mean_free_path_mm > 0
