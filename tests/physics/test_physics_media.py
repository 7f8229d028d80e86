"""Tests of sandlight.physics.media: the media the engine traces and the one resolution path."""

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.physics import media
from sandlight.physics.composition import compose
from sandlight.physics.medium import Traceable
from sandlight.sample import SandSample


def test_a_sample_resolves_to_its_composition_with_the_engine_settings():
    sample = SandSample.preset("red-dune")
    default = media.as_traceable("red-dune")
    assert isinstance(default, media.SandMedium) and default.composition == compose(sample)
    assert default.memory == media.DEFAULT_MEMORY == "packed" and default.films == "pendular"
    with_films = {**sample.to_dict(), "films": "pendular"}
    assert default.describe() == {**with_films, "geometry": "on-the-fly", "memory": "packed"}
    classic = media.as_traceable(sample, memory="none")
    assert classic.describe() == with_films  # memory 'none' recorded by omission
    assert media.engine_settings(classic.describe()) == (with_films, "on-the-fly", "none")
    cut = media.as_traceable(sample, memory="cut")
    assert cut.memory == "cut"
    assert cut.describe() == {**with_films, "geometry": "on-the-fly", "memory": "cut"}
    assert media.engine_settings(cut.describe()) == (with_films, "on-the-fly", "cut")
    assert media.engine_settings({"albedo": 0.5}) == ({"albedo": 0.5}, "on-the-fly", "none")


def test_explicit_geometry_resolves_to_a_packing_of_the_grains():
    from sandlight.physics.medium import native_medium
    from sandlight.physics.packing import generate_packing

    sample = SandSample(grain_size=0.4, grain_size_spread=1.0, aspect_ratio=1.0, sand=1.0, silt=0.0, clay=0.0)
    comp = compose(sample)
    pk = generate_packing(native_medium(comp, 550.0), reference_mm=0.4, lateral_mm=2.5, depth_mm=2.5, seed=1)
    packed = media.as_traceable(sample, geometry="explicit", packing=pk)
    assert isinstance(packed, media.PackedSand) and packed.packing is pk
    assert packed.describe() == {**sample.to_dict(), "geometry": "explicit", "memory": "none"}
    r = sandlight.reflectance(packed, [550.0], rays=2000, seed=4, progress=False)
    same = sandlight.reflectance(sample, [550.0], rays=2000, seed=4, geometry="explicit", packing=pk, progress=False)
    assert r.values[0] == same.values[0] and (r.geometry, r.memory) == ("explicit", "none")
    assert r.sample == sample.to_dict()
    with pytest.raises(ParameterError, match="packing"):
        media.PackedSand(comp, "a packing")


def test_a_traceable_is_traced_as_it_is():
    lambert = media.LambertianSurface(0.5)
    assert media.as_traceable(lambert) is lambert
    for kwargs in (dict(geometry="explicit"), dict(memory="cut"), dict(packing=object())):
        with pytest.raises(ParameterError, match="geometry"):
            media.as_traceable(lambert, **kwargs)
    with pytest.raises(ParameterError, match="sample"):
        media.as_traceable({"iron_oxide": 0.01})
    with pytest.raises(ParameterError, match="memory"):
        media.SandMedium(compose(SandSample()), memory="forever")


def test_the_remembered_optical_constants_change_no_result():
    # native_medium and the dispersion groups remember the shipped constants at a wavelength
    # (shipped_index); the same tables looked up anew at every call (complex_index itself given
    # as the optical constants) give the same groups and the same numbers, bit for bit.
    from sandlight.optics import complex_index
    from sandlight.physics.medium import shipped_index

    sample = SandSample.preset("red-dune")
    wl = [450.0, 650.0, 1450.0, 2200.0]
    remembered = sandlight.reflectance(sample, wl, rays=1500, seed=3, progress=False)
    looked_up = media.SandMedium.from_sample(sample, optical_constants=complex_index)
    anew = sandlight.reflectance(looked_up, wl, rays=1500, seed=3, progress=False)
    assert remembered.groups == anew.groups and len(anew.groups) > 1
    assert np.array_equal(remembered.values, anew.values) and np.array_equal(remembered.stderr, anew.stderr)
    assert shipped_index("water", 1450.0) == complex(complex_index("water", 1450.0))


def test_the_reference_media_describe_themselves():
    assert media.IsotropicScatterers(0.9).describe() == {"reference": "isotropic scatterers", "albedo": 0.9}
    assert media.IsotropicScatterers(0.9, depth=2.0).describe()["depth"] == 2.0
    assert media.LambertianSurface(0.3).describe() == {"reference": "lambertian surface", "albedo": 0.3}
    assert all(isinstance(m, Traceable) for m in (media.IsotropicScatterers(0.5), media.LambertianSurface(0.5)))


def test_the_engine_traces_the_isotropic_reference_as_the_half_space():
    # The same medium, rays and random streams: the same counts as isotropic_halfspace.
    r = sandlight.reflectance(media.IsotropicScatterers(0.9), [550.0], rays=5000, seed=1, progress=False)
    rho, se = sandlight.isotropic_halfspace(0.9, rays=5000, seed=1)
    assert r.values[0] == rho and r.stderr[0] == se
    assert r.sample == {"reference": "isotropic scatterers", "albedo": 0.9}


def test_a_user_class_with_the_two_methods_is_traceable():
    class GreyWall:
        """An ideal diffuse reflector of albedo 0.7, written by a user."""

        def medium(self, wavelength_nm):
            return media.LambertianSurface(0.7).medium(wavelength_nm)

        def describe(self):
            return {"wall": "grey"}

    r = sandlight.reflectance(GreyWall(), [500.0, 600.0], rays=20_000, seed=2, progress=False)
    # A Lambertian surface reflects its albedo whatever the incidence.
    assert np.all(np.abs(r.values - 0.7) < 4 * np.sqrt(0.7 * 0.3 / 20_000))
    assert r.sample == {"wall": "grey"}
    b = sandlight.brdf(GreyWall(), 550.0, rays=20_000, stacks=4, slices=4, seed=2, progress=False)
    assert b.sample == {"wall": "grey"}
    assert abs(b.normal_reflectance - 0.7) < 4 * b.reduced.normal_reflectance_stderr
