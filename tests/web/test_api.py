"""The explorer's JSON API with the ASGI test client: schema, validate, spectrum, colour, BRDF.

Answers are checked against the Python API they stand for (the same model, the same colour
pipeline), and every user mistake against the same ParameterError the Python API raises."""

import math

import numpy as np
import pytest

import colour
from sandlight.colour import sample_lab
from sandlight.errors import ParameterError
from sandlight.sample import PARAMETERS, SandSample
from sandlight.web.spectra import bank


def test_schema_lists_every_parameter_with_unit_domain_default_and_the_presets(client):
    body = client.get("/api/schema").json()
    assert [p["name"] for p in body["parameters"]] == [p.name for p in PARAMETERS]
    for shown, p in zip(body["parameters"], PARAMETERS):
        assert shown["unit"] == p.unit and shown["allowed"] == p.allowed and shown["kind"] == p.kind
        assert shown["default"] == ("inf" if p.default == math.inf else p.default)
    assert set(body["presets"]) == set(SandSample.presets())
    assert SandSample.from_dict(body["presets"]["red-dune"]) == SandSample.preset("red-dune")
    assert {m["name"] for m in body["models"]} == {m.name_ for m in bank().models}
    assert all(m["holdout_rms"] > 0 for m in body["models"])


def test_validate_answers_the_full_sample(client):
    res = client.post("/api/validate", json={"sample": {"preset": "red-dune", "saturation": 0.5}})
    assert res.status_code == 200
    assert SandSample.from_dict(res.json()["sample"]) == SandSample.preset("red-dune").replace(saturation=0.5)


def _python_error(**values) -> ParameterError:
    with pytest.raises(ParameterError) as info:
        SandSample.from_dict(values)
    return info.value


@pytest.mark.parametrize(
    "values",
    [
        {"iron_oxide": 0.5},
        {"iron_oxide": "0.02"},
        {"iron_oxide_form": "dust"},
        {"grain": 0.3},
        {"preset": "moon"},
        {"sand": 0.9, "silt": 0.04, "clay": 0.01},
        {"porosity": None},
    ],
)
def test_a_bad_sample_is_a_400_naming_parameter_value_and_domain_as_the_python_api_does(client, values):
    expected = _python_error(**values)
    for path in ("/api/validate", "/api/spectrum", "/api/colour", "/api/brdf"):
        res = client.post(path, json={"sample": values})
        assert res.status_code == 400, (path, res.text)
        body = res.json()
        assert body["error"] == "parameter" and body["parameter"] == expected.name
        assert body["allowed"] == expected.allowed and body["message"] == str(expected)
        assert "Traceback" not in res.text


@pytest.mark.parametrize(
    ("content", "kind", "status", "named"),
    [
        (b"{not json", "application/json", 400, "body"),
        (b"[1, 2]", "application/json", 400, "body"),
        (b'{"sample": {"iron_oxide": NaN}}', "application/json", 400, "body"),
        (b'{"sample": {}}', "text/plain", 415, None),
        (b'{"sampel": {}}', "application/json", 400, "sampel"),
        (b'{"sample": 3}', "application/json", 400, "sample"),
    ],
)
def test_malformed_bodies_are_refused_with_a_clear_4xx(client, content, kind, status, named):
    res = client.post("/api/spectrum", content=content, headers={"content-type": kind})
    assert res.status_code == status, res.text
    body = res.json()
    if named is not None:
        assert body["parameter"] == named
    assert body["message"] and "Traceback" not in res.text


def test_spectrum_is_the_banks_prediction_with_the_model_and_its_holdout_error(client):
    sample = SandSample.preset("red-dune").replace(iron_oxide=0.03)
    body = client.post("/api/spectrum", json={"sample": sample.to_dict()}).json()
    values, used = bank().predict([sample], return_models=True)
    assert body["covered"] and body["model"] == used[0]
    np.testing.assert_allclose(body["reflectance"], values[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(body["wavelengths_nm"], bank().wavelengths_)
    assert body["holdout_rms"] == pytest.approx(bank().model(used[0]).holdout_scores_["rms_error_overall"])
    assert body["model"] in body["description"]


def test_a_sample_outside_every_models_domain_is_said_so_and_offered_monte_carlo(client):
    body = client.post("/api/spectrum", json={"sample": {"depth_mm": 5}}).json()
    assert body["covered"] is False and body["model"] is None
    assert "depth_mm" in body["reason"]
    assert body["monte_carlo"]["endpoint"] == "/api/jobs/reflectance"
    assert body["monte_carlo"]["wavelength_range_nm"] == [350.0, 2500.0]
    colour_body = client.post("/api/colour", json={"sample": {"depth_mm": 5}}).json()
    assert colour_body["a"]["covered"] is False and "depth_mm" in colour_body["a"]["reason"]


def test_colour_is_sandlights_colour_of_the_prediction_and_delta_e_is_ciede2000(client):
    a, b = SandSample.preset("red-dune"), SandSample.preset("yellow-dune")
    body = client.post("/api/colour", json={"sample": "red-dune", "compare": "yellow-dune"}).json()
    np.testing.assert_allclose(body["a"]["lab_d50"], sample_lab(a), atol=1e-9)
    np.testing.assert_allclose(body["b"]["lab_d50"], sample_lab(b), atol=1e-9)
    np.testing.assert_allclose(body["a"]["lab_d65"], sample_lab(a, illuminant="D65"), atol=1e-9)
    expected = colour.delta_E(sample_lab(a), sample_lab(b), method="CIE 2000")
    assert body["delta_e2000"] == pytest.approx(float(expected), abs=1e-9)
    rgb = np.round(np.array(body["a"]["srgb"]) * 255).astype(int)
    assert body["a"]["hex"] == "#" + "".join(f"{c:02x}" for c in rgb)
    # red sand is redder (a* larger) than it is blue, and the same sample differs by nothing
    assert body["a"]["lab_d50"][1] > 20
    same = client.post("/api/colour", json={"sample": "red-dune", "compare": "red-dune"}).json()
    assert same["delta_e2000"] == pytest.approx(0.0, abs=1e-12)


def test_more_iron_oxide_makes_a_darker_redder_colour(client):
    light = client.post("/api/colour", json={"sample": {"preset": "red-dune", "iron_oxide": 0.01}}).json()["a"]
    dark = client.post("/api/colour", json={"sample": {"preset": "red-dune", "iron_oxide": 0.05}}).json()["a"]
    assert dark["lab_d50"][0] < light["lab_d50"][0] - 5  # L* falls


def test_brdf_maps_have_the_requested_grid_and_the_mirror_symmetry_of_the_model(client):
    res = client.post(
        "/api/brdf", json={"sample": "wet-beach", "incidence_deg": 40, "wavelength_nm": 600, "n_theta": 12, "n_phi": 24}
    )
    assert res.status_code == 200, res.text
    body = res.json()
    f = np.array(body["polar"]["f"])
    assert f.shape == (12, 24) and np.all(f >= 0) and body["unit"] == "1/sr"
    # the light lies in the plane φ = 0: f(φ) = f(360° − φ)
    np.testing.assert_allclose(f, f[:, ::-1], rtol=1e-9, atol=1e-12)
    plane = np.array(body["principal_plane"]["f"])
    theta = np.array(body["principal_plane"]["theta_deg"])
    assert plane.shape == theta.shape and theta[0] < 0 < theta[-1]
    # albedo of the model is a reflectance
    assert 0 < body["albedo"] < 1


@pytest.mark.parametrize(
    ("field", "value", "named"),
    [
        ("wavelength_nm", 1000, "wavelength_nm"),
        ("wavelength_nm", "green", "wavelength_nm"),
        ("incidence_deg", 95, "incidence_deg"),
        ("n_theta", 1000, "n_theta"),
        ("n_phi", 2.5, "n_phi"),
    ],
)
def test_brdf_bad_options_are_named(client, field, value, named):
    res = client.post("/api/brdf", json={"sample": "red-dune", field: value})
    assert res.status_code == 400 and res.json()["parameter"] == named, res.text


def test_an_error_in_the_comparison_sample_names_it(client):
    res = client.post("/api/colour", json={"sample": "red-dune", "compare": {"iron_oxide": 0.5}})
    assert res.status_code == 400
    body = res.json()
    assert body["parameter"] == "compare.iron_oxide" and body["allowed"] == "a real number in [0, 0.1]"
    assert body["message"].startswith("compare.iron_oxide = 0.5 is not allowed")
