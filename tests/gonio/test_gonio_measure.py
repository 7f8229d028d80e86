"""The goniophotometer driven by the transport engine, against exact answers."""

import dataclasses
import hashlib
import math

import numpy as np
import pytest

import sandlight
from sandlight import _native
from sandlight.errors import ModelFileError, ParameterError
from sandlight.gonio import CollectorHemisphere, EquivalenceClasses, reduce_counts
from sandlight.gonio.measure import IsotropicScatterers, LambertianSurface, brdf, fixed_incidence
from sandlight.optics import complex_index
from sandlight.physics.media import PackedSand, as_traceable
from sandlight.physics.medium import native_medium
from sandlight.physics.packing import generate_packing, reference_grain_mm
from sandlight.physics.spectral_groups import spectral_groups
from sandlight.testing import synthetic_brdf

STACKS, SLICES = 7, 6


def z_ok(z, *, mean_tol):
    """Most z-scores within 4, none wild, no systematic bias."""
    assert np.all(np.isfinite(z))
    assert np.mean(np.abs(z) < 4) > 0.99
    assert abs(z.mean()) < mean_tol


def test_chandrasekhar_brdf_patch_by_patch():
    hemi = CollectorHemisphere(STACKS, SLICES)
    m = brdf(
        IsotropicScatterers(0.9), rays=2_000_000, stacks=STACKS, slices=SLICES, seed=1, method="pooled", progress=False
    )
    red = reduce_counts(hemi, m.counts, m.absorbed, m.launched, m.lost, method="pooled")
    expected = EquivalenceClasses(hemi).mean(
        synthetic_brdf.expected_brdf(hemi, synthetic_brdf.chandrasekhar_probabilities(hemi, 0.9))
    )
    z = (red.unique_absolute - expected) / red.unique_absolute_stderr
    z_ok(z, mean_tol=0.2)
    assert 0.8 < z.std() < 1.2


def test_lambertian_surface_gives_a_over_pi_everywhere():
    m = brdf(LambertianSurface(0.6), rays=500_000, stacks=STACKS, slices=SLICES, seed=2, progress=False)
    hemi = CollectorHemisphere(STACKS, SLICES)
    red = reduce_counts(hemi, m.counts, m.absorbed, m.launched, m.lost)
    z = (red.unique_absolute - 0.6 / math.pi) / red.unique_absolute_stderr
    z_ok(z, mean_tol=0.2)


def test_fixed_incidence_lambertian():
    r = fixed_incidence(
        LambertianSurface(0.5), incidence_deg=40, rays=300_000, stacks=STACKS, slices=SLICES, seed=3, progress=False
    )
    assert r.launched == 300_000 and r.absorbed + r.counts.sum() == r.launched
    z_ok((r.values - 0.5 / math.pi) / r.stderr, mean_tol=0.5)
    assert abs(r.reflectance - 0.5) < 4 * math.sqrt(0.25 / 300_000)


def test_sand_brdf_is_reduced_exactly_and_thread_independent():
    s = sandlight.SandSample.preset("red-dune")
    one = brdf(s, 650, rays=20_000, stacks=STACKS, slices=SLICES, seed=4, threads=1, progress=False)
    two = brdf(s, 650, rays=20_000, stacks=STACKS, slices=SLICES, seed=4, threads=2, progress=False)
    assert np.array_equal(one.counts, two.counts)
    f = one.values
    assert np.array_equal(f, f.T)  # reciprocity holds exactly after reduction
    omega_p = CollectorHemisphere(STACKS, SLICES).projected_solid_angles
    assert (f[0] * omega_p).sum() == pytest.approx(1.0, abs=1e-12)


class CountedLambertian:
    """LambertianSurface(0.4) whose trials are counted per batch; Ctrl-C (KeyboardInterrupt)
    at batch ``interrupt_at`` (0-based), as a user would press it during a run."""

    def __init__(self, interrupt_at: int | None = None):
        self.surface, self.interrupt_at, self.traced = LambertianSurface(0.4), interrupt_at, []

    def describe(self) -> dict:
        return self.surface.describe()  # the same run as the plain surface: same checkpoint key

    def medium(self, wavelength_nm: float):
        native, outer = self.surface.medium(wavelength_nm), self

        class Counted:
            def brdf_counts(self, *args):
                if len(outer.traced) == outer.interrupt_at:
                    raise KeyboardInterrupt
                counts, absorbed, launched, lost = native.brdf_counts(*args)
                outer.traced.append(int(launched.sum()))
                return counts, absorbed, launched, lost

        return Counted()


def test_checkpointed_run_resumes_to_the_same_counts(tmp_path):
    ck = tmp_path / "run.checkpoint.npz"
    run = {"rays": 40_000, "stacks": STACKS, "slices": SLICES, "seed": 5, "progress": False}
    full = brdf(LambertianSurface(0.4), **run)

    # Ctrl-C during the third batch, with a checkpoint after every batch.
    interrupted = CountedLambertian(interrupt_at=2)
    with pytest.raises(KeyboardInterrupt):
        brdf(interrupted, checkpoint=ck, checkpoint_seconds=0.0, **run)
    assert ck.exists() and len(interrupted.traced) == 2
    before = sum(interrupted.traced)
    assert 0 < before < run["rays"]
    resumed_run = CountedLambertian()
    resumed = brdf(resumed_run, checkpoint=ck, **run)
    # Only the rays after the checkpoint are traced again, and the counts are those of one run.
    assert sum(resumed_run.traced) == run["rays"] - before
    assert np.array_equal(resumed.counts, full.counts) and not ck.exists()


def test_bad_inputs():
    with pytest.raises(ParameterError, match="stacks"):
        brdf(LambertianSurface(0.5), rays=10, stacks=1)
    with pytest.raises(ParameterError, match="checkpoint_seconds"):
        brdf(LambertianSurface(0.5), rays=10, checkpoint_seconds=-1.0)
    with pytest.raises(ParameterError, match="sample"):
        brdf(42, rays=10)
    with pytest.raises(ParameterError, match="incidence_deg"):
        fixed_incidence(LambertianSurface(0.5), incidence_deg=95, rays=10)


def _lambertian_run(checkpoint, rays=40_000):
    return brdf(
        LambertianSurface(0.4), rays=rays, stacks=STACKS, slices=SLICES, seed=5, checkpoint=checkpoint, progress=False
    )


def _valid_checkpoint(tmp_path, rays=40_000):
    """A checkpoint of `_lambertian_run` saved after its first batch, and its members."""
    from unittest import mock

    import sandlight._runner as runner

    ck = tmp_path / "run.checkpoint.npz"
    original = runner.run_in_batches

    def interrupted(run_batch, total, **kw):
        def on_checkpoint(done):
            kw["on_checkpoint"](done)
            raise KeyboardInterrupt

        return original(run_batch, total, **{**kw, "checkpoint_seconds": -1.0, "on_checkpoint": on_checkpoint})

    with mock.patch("sandlight.gonio.measure.run_in_batches", interrupted), pytest.raises(KeyboardInterrupt):
        _lambertian_run(ck, rays)
    with np.load(ck) as z:
        members = {name: z[name] for name in z.files}
    return ck, members


@pytest.mark.parametrize(
    "corrupt, fault",
    [
        (lambda ck, m: ck.write_bytes(b""), "not a zip"),
        (lambda ck, m: ck.write_bytes(ck.read_bytes()[: len(ck.read_bytes()) // 2]), "not a zip"),
        (lambda ck, m: np.savez(ck, **{**m, "done": np.array(-5)}), "'done' = -5"),
        (lambda ck, m: np.savez(ck, **{**m, "done": np.array(10**6)}), "'done' = 1000000"),
        (lambda ck, m: np.savez(ck, **{**m, "done": np.array(100.0)}), "'done' = 100.0"),
        (lambda ck, m: np.savez(ck, **{**m, "counts": m["counts"].astype(float) + 0.5}), "'counts' has shape"),
        (lambda ck, m: np.savez(ck, **{**m, "lost": m["lost"][:-1]}), "'lost' has shape"),
        (lambda ck, m: np.savez(ck, **{**m, "key": np.array("not this run")}), "different run"),
        (lambda ck, m: np.savez(ck, **{**m, "key": np.array(7)}), "'key' is not a string"),
        (lambda ck, m: np.savez(ck, **{**m, "extra": np.zeros(3)}), "not a brdf checkpoint"),
        (lambda ck, m: np.savez(ck, **{k: v for k, v in m.items() if k != "absorbed"}), "not a brdf checkpoint"),
        (lambda ck, m: np.savez(ck, **{**m, "launched": np.zeros(10**6, np.uint64)}), "bytes, at most"),
        (lambda ck, m: np.savez(ck, **{**m, "key": np.array([m["key"]], dtype=object)}), "unreadable"),
    ],
)
def test_a_malformed_checkpoint_is_refused_naming_the_file_and_the_fault(tmp_path, corrupt, fault):
    ck, members = _valid_checkpoint(tmp_path)
    assert 0 < int(members["done"]) < 40_000
    corrupt(ck, members)
    with pytest.raises(ModelFileError, match="delete it to start afresh") as info:
        _lambertian_run(ck)
    assert str(ck) in str(info.value) and fault in str(info.value)
    assert ck.exists()  # left for the user to look at


def test_a_valid_checkpoint_is_accepted_by_the_checks(tmp_path):
    ck, _ = _valid_checkpoint(tmp_path)
    full = _lambertian_run(None)
    assert np.array_equal(_lambertian_run(ck).counts, full.counts) and not ck.exists()


def test_too_few_rays_warn_with_the_number_of_nan_values():
    from sandlight.gonio.measure import rays_for_every_patch

    r = CollectorHemisphere(STACKS, SLICES).n_patches
    with pytest.warns(UserWarning, match=r"of \d+ BRDF values are NaN: \d+ of 37 incoming patches") as record:
        short = brdf(LambertianSurface(0.5), rays=20, stacks=STACKS, slices=SLICES, seed=1, progress=False)
    n_nan = int(np.isnan(short.unique_values).sum())
    assert n_nan > 0 and f"{n_nan} of {short.unique_values.size}" in str(record[0].message)
    assert f"at least about {rays_for_every_patch(r)} rays" in str(record[0].message)
    # r ln(100 r) trials leave a patch empty in about one run in 100: this one warns of nothing.
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        full = brdf(
            LambertianSurface(0.5), rays=rays_for_every_patch(r), stacks=STACKS, slices=SLICES, seed=1, progress=False
        )
    assert np.isfinite(full.unique_values).all()


# Spectral path sharing (docs/transport.md) ----------------------------------------------------


def absorption_only(name):
    """The preset with every real index frozen at its 550 nm value: only absorption varies."""

    def index(material: str, wavelength_nm: float) -> complex:
        return complex(complex_index(material, 550.0).real, complex_index(material, wavelength_nm).imag)

    return dataclasses.replace(as_traceable(name), optical_constants=index)


def sharing_z(measure, values, traced, wl, seeds) -> np.ndarray:
    """z = (shared − independent)/√(se_s² + se_i²) over wavelengths and runs: ``measure(traced,
    wavelengths, seed)`` runs an instrument, ``values(result)`` gives (values, standard errors);
    for each shared run of seed s, wavelength k is measured on its own with seed 100 + 10 s + k,
    so that the independent errors are independent."""
    z = []
    for seed in seeds:
        shared = measure(traced, wl, seed)
        assert all(b.squares is not None for b in shared)
        for k, lam in enumerate(wl):
            ind = measure(traced, lam, 100 + 10 * seed + k)
            assert ind.squares is None
            (s, se_s), (i, se_i) = values(shared[k]), values(ind)
            z.append((s - i) / np.hypot(se_s, se_i))
    z = np.concatenate(z)
    print(f"{z.size} z: mean {z.mean():+.3f}, spread {z.std(ddof=1):.3f}, max |z| {np.abs(z).max():.2f}")
    return z


def z_unbiased(z: np.ndarray) -> None:
    """Shared and independent agree: z of mean within 0.2 and spread within 0.8–1.2."""
    assert np.all(np.isfinite(z))
    assert abs(z.mean()) < 0.2, z.mean()
    assert 0.8 < z.std(ddof=1) < 1.2, z.std(ddof=1)


def absolute_values(b):
    """The absolute unique BRDF values of a uniform-incidence run, with their standard errors."""
    return b.reduced.unique_absolute, b.reduced.unique_absolute_stderr


def brdf_runs(rays: int, stacks: int = STACKS, slices: int = SLICES):
    """``measure`` for `sharing_z`: uniform-incidence runs of ``rays`` trials."""
    return lambda traced, wl, seed: brdf(traced, wl, rays=rays, stacks=stacks, slices=slices, seed=seed, progress=False)


@pytest.mark.parametrize(
    "traced, wl",
    [
        # Iron-oxide absorption: ρ from about 0.04 to 0.6 over 450–650 nm, one group.
        (absorption_only("red-dune"), [450.0, 520.0, 590.0, 650.0]),
        # Real dispersion, grouped by the default tolerance.
        ("ottawa-quartz", [400.0, 500.0, 600.0, 700.0]),
    ],
    ids=["absorption-only", "ottawa-quartz"],
)
def test_shared_brdf_agrees_with_independent_measurements(traced, wl):
    z_unbiased(sharing_z(brdf_runs(60_000), absolute_values, traced, wl, seeds=[1]))


def test_shared_explicit_brdf_agrees_with_independent_measurements():
    # The explicit reference (PackedSand: a packing of red-dune's grains in a 2 mm box, its
    # fines on the fly) over 450–650 nm (real dispersion, one group), on a coarser 5 × 4
    # hemisphere: 13 patches, 41 classes.
    comp = as_traceable("red-dune").composition
    pk = generate_packing(
        native_medium(comp, 550.0), reference_mm=reference_grain_mm(comp), lateral_mm=2, depth_mm=2, seed=1
    )
    traced = as_traceable("red-dune", geometry="explicit", packing=pk)
    assert isinstance(traced, PackedSand)
    wl = [450.0, 520.0, 590.0, 650.0]
    assert len(spectral_groups(traced.composition, np.array(wl))) == 1
    z_unbiased(sharing_z(brdf_runs(10_000, 5, 4), absolute_values, traced, wl, seeds=[1, 2, 3]))


def test_shared_sums_do_not_depend_on_the_thread_count():
    run = {"rays": 20_000, "stacks": STACKS, "slices": SLICES, "seed": 3, "progress": False}
    one = brdf("red-dune", [500.0, 600.0], threads=1, **run)
    two = brdf("red-dune", [500.0, 600.0], threads=2, **run)
    assert one == two
    assert one[0].counts.dtype == np.float64 and not np.array_equal(one[0].counts, np.round(one[0].counts))


def test_no_sharing_is_the_single_wavelength_measurement_bit_for_bit():
    run = {"rays": 20_000, "stacks": STACKS, "slices": SLICES, "seed": 2, "progress": False}
    both = brdf("red-dune", [550.0, 650.0], share=False, **run)
    assert [b.wavelength_nm for b in both] == [550.0, 650.0]
    assert both[1] == brdf("red-dune", 650.0, **run) == brdf("red-dune", [650.0], **run)[0]
    # The counts of this run before sharing existed (scripts/dev/fingerprint.py, 'brdf/red-dune').
    digest = hashlib.sha256(np.ascontiguousarray(both[1].counts, dtype=np.int64).tobytes()).hexdigest()
    assert digest == "06d4d54b82b28ec0c840ff9843608b35e5aed9bf140755e81bda7c4188e4172d"
    assert both[1].counts.sum() == 14065


def test_media_that_cannot_share_are_measured_wavelength_by_wavelength():
    run = {"rays": 5_000, "stacks": STACKS, "slices": SLICES, "seed": 2, "progress": False}
    shared = brdf(LambertianSurface(0.5), [500.0, 600.0], **run)
    assert shared == brdf(LambertianSurface(0.5), [500.0, 600.0], share=False, **run)
    assert shared[0].squares is None


def test_an_interrupted_shared_run_resumes_without_retracing_finished_groups(tmp_path, monkeypatch):
    run = {"rays": 8_000, "stacks": STACKS, "slices": SLICES, "seed": 6, "progress": False}
    wl = [400.0, 1500.0]  # two groups: quartz's index differs by more than the tolerance
    full = brdf("ottawa-quartz", wl, **run)
    native_group, traced = _native.SpectralGroup, []

    class Counted:
        """SpectralGroup counting its traced trials; Ctrl-C in the first batch of group
        ``interrupt_at`` (1-based, counted over the groups made)."""

        fixed_one, square_one = native_group.fixed_one, native_group.square_one
        made, interrupt_at = 0, 2

        def __init__(self, media):
            Counted.made += 1
            self.group, self.interrupt = native_group(media), Counted.made == Counted.interrupt_at

        def brdf_sums(self, *args):
            if self.interrupt:
                raise KeyboardInterrupt
            traced.append(args[5])  # n_rays
            return self.group.brdf_sums(*args)

    ck = tmp_path / "run.npz"
    monkeypatch.setattr(_native, "SpectralGroup", Counted)
    with pytest.raises(KeyboardInterrupt):
        brdf("ottawa-quartz", wl, checkpoint=ck, checkpoint_seconds=0.0, **run)
    assert sum(traced) == run["rays"] and sorted(p.name for p in tmp_path.iterdir()) == ["run.npz.0"]
    traced.clear()
    Counted.interrupt_at = None
    assert brdf("ottawa-quartz", wl, checkpoint=ck, **run) == full
    assert sum(traced) == run["rays"] and not any(tmp_path.iterdir())  # group 1 from its checkpoint


def test_bad_sharing_inputs_name_the_parameter():
    with pytest.raises(ParameterError, match=r"share.*'yes'.*True or False"):
        brdf("red-dune", [500.0, 600.0], rays=10, share="yes")
    with pytest.raises(ParameterError, match=r"dispersion_tolerance.*\[0"):
        brdf("red-dune", [500.0, 600.0], rays=10, dispersion_tolerance=2.0)
    with pytest.raises(ParameterError, match=r"wavelength_nm.*\[350, 2500\]"):
        brdf("red-dune", [500.0, 3000.0], rays=10)


# The classic instrument (fixed incidence) with shared paths ------------------------------------

FIXED = {"incidence_deg": 30.0, "azimuth_deg": 20.0, "stacks": STACKS, "slices": SLICES, "progress": False}


@pytest.mark.parametrize(
    "preset, wl",
    [("red-dune", [450.0, 520.0, 590.0, 650.0]), ("ottawa-quartz", [400.0, 500.0, 600.0, 700.0])],
)
def test_shared_fixed_incidence_agrees_with_independent_measurements(preset, wl):
    # Real presets with their dispersion (one group each at the default tolerance): the 37
    # values f_j per wavelength, 5 shared runs.
    def measure(traced, wl, seed):
        return fixed_incidence(traced, wl, rays=40_000, seed=seed, **FIXED)

    z_unbiased(sharing_z(measure, lambda b: (b.values, b.stderr), preset, wl, seeds=range(1, 6)))


def test_shared_fixed_incidence_does_not_depend_on_the_thread_count():
    run = {"rays": 20_000, "seed": 3, **FIXED}
    one, two = (fixed_incidence("red-dune", [500.0, 600.0], threads=t, **run) for t in (1, 2))
    for a, b in zip(one, two):
        for name in ("counts", "squares", "values", "stderr"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        assert (a.absorbed, a.launched, a.lost) == (b.absorbed, b.launched, b.lost)
    a = one[0]
    assert a.counts.dtype == np.float64 and not np.array_equal(a.counts, np.round(a.counts))
    assert a.launched == 20_000 and a.counts.sum() + a.absorbed + a.lost == pytest.approx(20_000, rel=1e-12)
    assert [b.wavelength_nm for b in one] == [500.0, 600.0]


def test_fixed_incidence_without_sharing_is_the_single_wavelength_measurement_bit_for_bit():
    run = {"rays": 20_000, "seed": 2, **FIXED}
    both = fixed_incidence("red-dune", [550.0, 650.0], share=False, **run)
    one = fixed_incidence("red-dune", 650.0, **run)
    assert both[1].squares is None and one.squares is None
    np.testing.assert_array_equal(both[1].counts, one.counts)
    np.testing.assert_array_equal(both[1].values, one.values)
    # The counts of this run before sharing existed (pinned from commit 2dcd636).
    digest = hashlib.sha256(np.ascontiguousarray(one.counts, dtype=np.int64).tobytes()).hexdigest()
    assert digest == "d61f5d6793a927f6423d583f2b7202cac0d03dee2358d71fa170396b87a841dd"
    assert (int(one.counts.sum()), one.absorbed, one.launched, one.lost) == (13701, 6299, 20_000, 0)
    # A medium that cannot share is measured wavelength by wavelength.
    lambert = fixed_incidence(LambertianSurface(0.5), [500.0, 600.0], **run)
    assert lambert[0].squares is None and lambert[0].counts.dtype == np.uint64


def test_bad_fixed_incidence_inputs_name_the_parameter():
    run = {"incidence_deg": 30.0, "rays": 10, "progress": False}
    with pytest.raises(ParameterError, match=r"share.*'yes'.*True or False"):
        fixed_incidence("red-dune", [500.0, 600.0], share="yes", **run)
    with pytest.raises(ParameterError, match=r"dispersion_tolerance.*\[0"):
        fixed_incidence("red-dune", [500.0, 600.0], dispersion_tolerance=2.0, **run)
    with pytest.raises(ParameterError, match=r"wavelength_nm.*\[350, 2500\]"):
        fixed_incidence("red-dune", [500.0, 3000.0], **run)
    with pytest.raises(ParameterError, match="azimuth_deg"):
        fixed_incidence("red-dune", [500.0, 600.0], **{**run, "azimuth_deg": math.nan})
    with pytest.raises(ParameterError, match="incidence_deg"):
        fixed_incidence("red-dune", [500.0, 600.0], **{**run, "incidence_deg": 90.0})


def test_shared_squares_are_read_from_their_two_words_exactly():
    from sandlight.gonio.measure import _weight_sums, _zero_sums

    sums = _zero_sums(1, 2, 1)
    one = _native.SpectralGroup.fixed_one
    sums["launched"][:] = 3
    sums["escaped"][0, :, 0] = [int(1.5 * one), 1]  # Σ F = 1.5 and 2⁻³²
    # Σ F² = 2.25 (high word 2, low 2⁶²) and the square of the smallest weight, 2⁻⁶⁴ (low word 1),
    # which a square rounded to any coarser scale would have counted as 0.
    sums["squares"][0, :, 0] = [[2, 1 << 62], [0, 1]]
    counts, *_, squares = _weight_sums(sums, 0)
    np.testing.assert_array_equal(squares[0], [2.25, 2.0**-64])
    np.testing.assert_array_equal(counts[0], [1.5, 2.0**-32])
