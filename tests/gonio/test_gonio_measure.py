"""The goniophotometer driven by the transport engine, against exact answers."""

import math

import numpy as np
import pytest

import sandlight
from sandlight.errors import ModelFileError, ParameterError
from sandlight.gonio import CollectorHemisphere, EquivalenceClasses, reduce_counts
from sandlight.gonio.measure import IsotropicScatterers, LambertianSurface, brdf, fixed_incidence
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
