"""Tests of sandlight.sample: parameter table, construction, files, presets and errors."""

import dataclasses
import importlib.util
import json
import math
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from sandlight.errors import ModelFileError, ParameterError
from sandlight.sample import PARAMETERS, SEPARATES_TOLERANCE, SandSample

FLOATS = [p for p in PARAMETERS if p.kind == "float"]
REQUIRED_PRESETS = ["ottawa-quartz", "red-dune", "yellow-dune", "wet-beach", "gds76-hematite-quartz", "ottawa-gds74"]
ROOT = Path(__file__).resolve().parents[1]


def assert_names(exc: ParameterError, name: str, value, *fragments: str) -> None:
    """The message names the parameter, the offending value and what is allowed."""
    text = str(exc)
    assert exc.name == name and name in text
    assert repr(value) in text
    for fragment in fragments:
        assert fragment in text


# -- the table and the defaults ------------------------------------------------------------


def test_fields_follow_the_parameter_table_in_order():
    assert [f.name for f in dataclasses.fields(SandSample)] == [p.name for p in PARAMETERS]


def test_issue_parameters_and_additions():
    added = {p.name for p in PARAMETERS if p.added}
    assert added == {
        "film_saturation",
        "iron_oxide_particle_size_um",
        "depth_mm",
        "host_absorption",
        "host_scattering",
        "coating_coverage",
    }
    form = SandSample.parameter("iron_oxide_form")
    assert form.kind == "choice" and form.choices == ("coating", "mixed", "particles")
    assert SandSample.parameter("grain_size").unit == "mm"
    assert SandSample.parameter("iron_oxide_particle_size_um").unit == "µm"


def test_defaults():
    s = SandSample()
    expected = dict(
        iron_oxide=0.01,
        hematite_ratio=0.5,
        magnetite=0.0,
        iron_oxide_form="coating",
        coating_iron_share=0.2,
        saturation=0.0,
        film_saturation=0.15,
        sand=0.95,
        silt=0.04,
        clay=0.01,
        grain_size=0.25,
        grain_size_spread=1.4,
        aspect_ratio=1.4,
        porosity=0.40,
        iron_oxide_particle_size_um=1.0,
        depth_mm=math.inf,
        host_absorption=1.0,
        host_scattering=0.0,
        coating_coverage=1.0,
    )
    assert {p.name: getattr(s, p.name) for p in PARAMETERS} == expected
    assert all(getattr(s, p.name) == p.default for p in PARAMETERS)


def test_domains_as_specified():
    domains = {p.name: (p.low, p.high) for p in FLOATS}
    assert domains == {
        "iron_oxide": (0, 0.10),
        "hematite_ratio": (0, 1),
        "magnetite": (0, 0.05),
        "coating_iron_share": (0.01, 1),
        "saturation": (0, 1),
        "film_saturation": (0, 1),
        "sand": (0.85, 1),
        "silt": (0, 0.15),
        "clay": (0, 0.10),
        "grain_size": (0.05, 2.0),
        "grain_size_spread": (1, 3),
        "aspect_ratio": (1, 3),
        "porosity": (0.25, 0.55),
        "iron_oxide_particle_size_um": (0.1, 50),
        "depth_mm": (0, math.inf),
        "host_absorption": (0, 10),
        "host_scattering": (0, 100),
        "coating_coverage": (0, 1),
    }
    assert [p.name for p in PARAMETERS if p.low_open] == ["depth_mm", "coating_coverage"]


# The separates are checked jointly: their domain ends come with partners summing to 1.
SEPARATE_ENDS = {
    "sand": [dict(sand=1.0, silt=0.0, clay=0.0), dict(sand=0.85, silt=0.15, clay=0.0)],
    "silt": [dict(sand=1.0, silt=0.0, clay=0.0), dict(sand=0.85, silt=0.15, clay=0.0)],
    "clay": [dict(sand=0.96, silt=0.04, clay=0.0), dict(sand=0.9, silt=0.0, clay=0.1)],
}


@pytest.mark.parametrize("p", FLOATS, ids=lambda p: p.name)
def test_domain_ends_are_accepted(p):
    ends = [p.high] + ([] if p.low_open else [p.low])
    for x in ends:
        changes = {p.name: x}
        if p.name in SEPARATE_ENDS:
            changes = next(c for c in SEPARATE_ENDS[p.name] if c[p.name] == x)
        assert getattr(SandSample(**changes), p.name) == x


def test_parameter_lookup_of_unknown_name():
    with pytest.raises(ParameterError) as info:
        SandSample.parameter("colour")
    assert_names(info.value, "parameter", "colour", "grain_size", "porosity")


# -- invalid values ------------------------------------------------------------------------


def _bad_values(p):
    """(case id, value) pairs outside the domain of float parameter p."""
    below = p.low if p.low_open else p.low - 0.01 * max(1.0, abs(p.low))
    cases = [
        ("below", below),
        ("far_below", -1.0),
        ("nan", math.nan),
        ("-inf", -math.inf),
        ("string", "abc"),
        ("numeric_string", "0.3"),
        ("empty_string", ""),
        ("none", None),
        ("true", True),
        ("false", False),
        ("list", [0.3]),
    ]
    if p.high != math.inf:
        cases += [("above", p.high + 0.01 * max(1.0, p.high)), ("+inf", math.inf)]
    return cases


BAD_FLOAT_CASES = [pytest.param(p, value, id=f"{p.name}-{case}") for p in FLOATS for case, value in _bad_values(p)]


@pytest.mark.parametrize(("p", "value"), BAD_FLOAT_CASES)
def test_invalid_float_raises_parameter_error(p, value):
    with pytest.raises(ParameterError) as info:
        SandSample(**{p.name: value})
    left = "(" if p.low_open else "["
    assert_names(info.value, p.name, value, f"{left}{p.low:g}, {p.high:g}]")
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("value", ["film", "Coating", "", None, 1, True])
def test_invalid_choice(value):
    with pytest.raises(ParameterError) as info:
        SandSample(iron_oxide_form=value)
    assert_names(info.value, "iron_oxide_form", value, "'coating'", "'mixed'", "'particles'")


def test_depth_accepts_inf_and_the_string_inf_only():
    assert SandSample(depth_mm=math.inf).depth_mm == math.inf
    assert SandSample(depth_mm="inf") == SandSample()
    assert SandSample(depth_mm=1e-3).depth_mm == 1e-3
    for bad in ("Infinity", "1", "-inf"):
        with pytest.raises(ParameterError):
            SandSample(depth_mm=bad)


@pytest.mark.parametrize("name", ["iron_oxide", "depth_mm", "iron_oxide_form"])
@pytest.mark.parametrize("value", [np.array([0.01, 0.02]), np.array(["coating", "mixed"]), [0.01], np.array([])])
def test_arrays_and_lists_are_refused_with_a_parameter_error(name, value):
    # One sample holds one value per parameter (issue 24 #16: numpy's "truth value ... ambiguous").
    with pytest.raises(ParameterError) as info:
        SandSample(**{name: value})
    assert info.value.name == name and info.value.value is value


def test_numbers_of_other_types_are_converted():
    s = SandSample(grain_size=np.float32(0.5), porosity=np.float64(0.3), sand=1, silt=0, clay=0)
    assert type(s.grain_size) is float and s.grain_size == 0.5
    assert type(s.sand) is float and s == SandSample(grain_size=0.5, porosity=0.3, sand=1.0, silt=0.0, clay=0.0)
    with pytest.raises(ParameterError):
        SandSample(grain_size=10**400)  # too large for a float


def test_separates_must_sum_to_one():
    with pytest.raises(ParameterError) as info:
        SandSample(sand=0.95, silt=0.04, clay=0.06)
    assert_names(info.value, "sand + silt + clay", 1.05, "sand=0.95", "silt=0.04", "clay=0.06", "1 within 1e-06")
    with pytest.raises(ParameterError):
        SandSample(sand=0.90, silt=0.04, clay=0.01)  # sums to 0.95
    # within the tolerance: accepted and stored as given
    assert SandSample(sand=0.95 + 0.5 * SEPARATES_TOLERANCE).sand == 0.95 + 0.5e-6


def test_separates_must_be_in_the_usda_sand_class():
    # every separate within its own domain and summing to 1, but silt + 1.5 clay = 0.19
    with pytest.raises(ParameterError) as info:
        SandSample(sand=0.86, silt=0.04, clay=0.10)
    assert_names(info.value, "silt + 1.5·clay", 0.19, "<= 0.15", "sand=0.86", "clay=0.1")
    # on the boundary (0.0 + 1.5 * 0.1 = 0.15): allowed
    assert SandSample(sand=0.90, silt=0.0, clay=0.10).clay == 0.10
    # sand below 0.85 is outside the sand separate's own domain
    with pytest.raises(ParameterError) as info:
        SandSample(sand=0.80, silt=0.15, clay=0.05)
    assert_names(info.value, "sand", 0.80, "[0.85, 1]")


def test_positional_and_unknown_keyword_arguments_are_refused():
    with pytest.raises(TypeError):
        SandSample(0.01)
    with pytest.raises(TypeError):
        SandSample(colour="red")


# -- value semantics -----------------------------------------------------------------------


def test_immutable():
    s = SandSample()
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.porosity = 0.3


def test_replace_validates_and_leaves_the_original():
    s = SandSample()
    wet = s.replace(saturation=1.0)
    assert wet.saturation == 1.0 and s.saturation == 0.0
    assert wet.replace(saturation=0.0) == s
    with pytest.raises(ParameterError) as info:
        s.replace(saturation=1.5)
    assert_names(info.value, "saturation", 1.5, "[0, 1]")
    with pytest.raises(ParameterError) as info:
        s.replace(colour="red")
    assert_names(info.value, "colour", "red", "allowed keys", "iron_oxide", "depth_mm")


def test_equality_and_hash():
    a, b = SandSample(grain_size=1), SandSample(grain_size=1.0)
    assert a == b and hash(a) == hash(b)
    c = a.replace(porosity=0.3)
    assert c != a
    assert len({a, b, c}) == 2
    assert {a: "x"}[b] == "x"


def test_repr_lists_every_parameter():
    text = repr(SandSample.preset("red-dune"))
    assert text.startswith("SandSample(")
    for p in PARAMETERS:
        assert f"{p.name}=" in text
    assert "iron_oxide=0.02" in text and "depth_mm=inf" in text


# -- presets -------------------------------------------------------------------------------


def test_required_presets_exist():
    names = SandSample.presets()
    assert set(REQUIRED_PRESETS) <= set(names)
    assert list(names) == sorted(names)


@pytest.mark.parametrize("name", SandSample.presets())
def test_preset_is_complete_documented_and_valid(name):
    text = (resources.files("sandlight") / "data" / "presets" / f"{name}.toml").read_text("utf-8")
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert header[0].startswith(f"# {name}:") and len(header) >= 5
    # every parameter set explicitly, so that a change of default does not move a preset
    assert set(tomllib.loads(text)) == {p.name for p in PARAMETERS}
    s = SandSample.preset(name)
    assert abs(s.sand + s.silt + s.clay - 1) <= SEPARATES_TOLERANCE


def test_preset_values():
    q = SandSample.preset("ottawa-quartz")
    assert (q.iron_oxide, q.magnetite, q.sand, q.silt, q.clay) == (0, 0, 1, 0, 0)
    assert (q.grain_size, q.grain_size_spread, q.aspect_ratio, q.porosity) == (0.4, 1.3, 1.2, 0.36)
    red, yellow = SandSample.preset("red-dune"), SandSample.preset("yellow-dune")
    assert red.iron_oxide_form == yellow.iron_oxide_form == "coating"
    assert red.iron_oxide == pytest.approx(0.02, abs=0.005)
    assert red.hematite_ratio == pytest.approx(0.8, abs=0.1)
    assert yellow.iron_oxide == pytest.approx(0.015, abs=0.005)
    assert yellow.hematite_ratio == pytest.approx(0.1, abs=0.1)
    beach = SandSample.preset("wet-beach")
    assert beach.magnetite == pytest.approx(0.01, abs=0.005)
    assert beach.saturation == pytest.approx(0.8, abs=0.1)
    assert beach.porosity == pytest.approx(0.42, abs=0.02)
    assert beach.iron_oxide < red.iron_oxide
    gds76 = SandSample.preset("gds76-hematite-quartz")
    assert (gds76.iron_oxide, gds76.hematite_ratio, gds76.iron_oxide_form) == (0.02, 1.0, "particles")
    assert gds76.grain_size < 0.25  # quartz < 250 µm: the median of the sand part is below it
    gds74 = SandSample.preset("ottawa-gds74")
    assert (gds74.iron_oxide, gds74.magnetite, gds74.sand) == (0, 0, 1)


@pytest.mark.parametrize("name", ["mars", "../red-dune", "", None, 3])
def test_unknown_preset_lists_the_available_ones(name):
    with pytest.raises(ParameterError) as info:
        SandSample.preset(name)
    assert_names(info.value, "preset", name, *REQUIRED_PRESETS)


# -- dicts and files -----------------------------------------------------------------------

ALL_SAMPLES = [SandSample(), SandSample(depth_mm=12.5, iron_oxide=1e-5)] + [
    SandSample.preset(n) for n in SandSample.presets()
]


@pytest.mark.parametrize("s", ALL_SAMPLES)
def test_dict_round_trip_through_strict_json(s):
    d = s.to_dict()
    assert list(d) == [p.name for p in PARAMETERS]
    text = json.dumps(d, allow_nan=False)  # strict JSON: no Infinity token
    assert SandSample.from_dict(json.loads(text)) == s
    assert SandSample.from_dict(d) == s


@pytest.mark.parametrize("s", ALL_SAMPLES)
def test_toml_round_trip(s, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(s.to_toml(), encoding="utf-8")
    assert SandSample.from_file(path) == s
    assert SandSample.from_file(str(path)) == s


def test_json_file(tmp_path):
    path = tmp_path / "s.json"
    path.write_text(
        json.dumps({"sample": {"preset": "red-dune", "saturation": 0.3, "depth_mm": "inf"}}), encoding="utf-8"
    )
    assert SandSample.from_file(path) == SandSample.preset("red-dune").replace(saturation=0.3)
    path.write_text(json.dumps(SandSample(depth_mm=4.0).to_dict()), encoding="utf-8")
    assert SandSample.from_file(path).depth_mm == 4.0


def test_toml_sample_table_and_preset_override(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[sample]\npreset = "wet-beach"\nsaturation = 0.1\ndepth_mm = 20\n', "utf-8")
    s = SandSample.from_file(path)
    assert s == SandSample.preset("wet-beach").replace(saturation=0.1, depth_mm=20.0)
    path.write_text("grain_size = 0.5\n", "utf-8")  # top-level keys, no preset: defaults
    assert SandSample.from_file(path) == SandSample(grain_size=0.5)


@pytest.mark.parametrize("suffix", [".toml", ".json", ".TOML"])
def test_empty_file_gives_defaults(tmp_path, suffix):
    path = tmp_path / f"empty{suffix}"
    path.write_text("\n", encoding="utf-8")
    assert SandSample.from_file(path) == SandSample()


@pytest.mark.parametrize(
    ("suffix", "text", "name", "value"),
    [
        (".toml", 'porosity = ""\n', "porosity", ""),
        (".toml", 'porosity = "0.4"\n', "porosity", "0.4"),
        (".toml", "porosity = nan\n", "porosity", math.nan),
        (".toml", "saturation = true\n", "saturation", True),
        (".toml", "grain_size = 3\n", "grain_size", 3),
        (".json", '{"porosity": null}', "porosity", None),
        (".json", '{"grain_size": ""}', "grain_size", ""),
        (".json", '{"grain_size": NaN}', "grain_size", math.nan),
        (".json", '{"grain_size": Infinity}', "grain_size", math.inf),
    ],
)
def test_invalid_value_in_file_names_parameter_and_file(tmp_path, suffix, text, name, value):
    path = tmp_path / f"bad{suffix}"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ParameterError) as info:
        SandSample.from_file(path)
    assert_names(info.value, name, value, str(path))


@pytest.mark.parametrize("text", ['colour = "red"\n', '[sample]\ncolour = "red"\n'])
def test_unknown_key_in_file(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ParameterError) as info:
        SandSample.from_file(path)
    assert_names(info.value, "colour", "red", "allowed keys: preset, iron_oxide", "grain_size", "depth_mm", str(path))


def test_keys_outside_the_sample_table_are_refused(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("porosity = 0.3\n[sample]\ngrain_size = 0.5\n", encoding="utf-8")
    with pytest.raises(ParameterError) as info:
        SandSample.from_file(path)
    assert_names(info.value, "porosity", 0.3, "[sample]")


def test_from_dict_refuses_non_mappings_and_unknown_keys():
    with pytest.raises(ParameterError):
        SandSample.from_dict([("porosity", 0.3)])
    with pytest.raises(ParameterError) as info:
        SandSample.from_dict({"porosity": 0.3, "grainsize": 0.5})
    assert_names(info.value, "grainsize", 0.5, "grain_size")


def test_a_sample_file_must_be_a_regular_file_of_bounded_size(tmp_path):
    from sandlight.sample import MAX_SAMPLE_FILE_BYTES

    (tmp_path / "dir.toml").mkdir()
    with pytest.raises(ParameterError, match="a regular file"):
        SandSample.from_file(tmp_path / "dir.toml")
    big = tmp_path / "big.toml"
    big.write_text("# padding\n" * (MAX_SAMPLE_FILE_BYTES // 10 + 1))
    with pytest.raises(ParameterError, match="at most"):
        SandSample.from_file(big)


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.toml"
    with pytest.raises(FileNotFoundError) as info:
        SandSample.from_file(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize(
    ("name", "content", "problem"),
    [
        ("broken.toml", b"porosity = \n", "TOML"),
        ("broken.toml", b"porosity = 0.3\nporosity = 0.4\n", "TOML"),
        ("broken.json", b'{"porosity": 0.3,', "JSON"),
        ("latin1.toml", "# caf\u00e9\n".encode("latin-1"), "TOML"),
        ("list.json", b"[0.3]", "list"),
        ("sample.yaml", b"porosity: 0.3\n", ".toml or .json"),
    ],
)
def test_unparsable_file_names_file_and_problem(tmp_path, name, content, problem):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(ModelFileError) as info:
        SandSample.from_file(path)
    assert str(path) in str(info.value) and problem in str(info.value)


def test_to_toml_is_commented():
    text = SandSample().to_toml()
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    assert len(lines) == len(PARAMETERS)
    assert 'iron_oxide_form = "coating"  # ' in text and "depth_mm = inf  # " in text
    assert "grain_size = 0.25  # median diameter (by mass) of the sand-sized grains [mm]" in text


# -- docs ----------------------------------------------------------------------------------


def test_generated_doc_sections_are_up_to_date():
    spec = importlib.util.spec_from_file_location("gen_sample_doc", ROOT / "scripts/docs/gen_sample_doc.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    text = (ROOT / "docs" / "sample.md").read_text(encoding="utf-8")
    assert gen.render(text) == text, "run python3 scripts/docs/gen_sample_doc.py"
    for p in PARAMETERS:
        assert f"| `{p.name}` |" in text
