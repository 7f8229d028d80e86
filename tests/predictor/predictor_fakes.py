"""A fake, deterministic stand-in for the Monte Carlo engine (module-level: workers import it).

The "true" reflectance is a smooth, known function of the sample parameters: iron oxide
darkens the blue end (more for the coating form), water darkens everything, coarse grains are
darker, fines brighten a little. The "Monte Carlo" result adds seeded Gaussian noise with the
binomial standard error √(r(1 − r)/rays), as the real engine's estimate would have. Standing in
for the engine itself (``engine_simulate``) it also takes the path memory, which scales it.
"""

import os
from pathlib import Path
from types import SimpleNamespace

import numpy as np

FORM_STRENGTH = {"coating": 1.0, "mixed": 0.7, "particles": 0.4}


def true_reflectance(params, wavelengths_nm):
    wl = (np.asarray(wavelengths_nm, dtype=float) - 550.0) / 150.0  # ~[-1, 1] over 400-700 nm
    iron = np.sqrt(params["iron_oxide"] / 0.10) * FORM_STRENGTH[params["iron_oxide_form"]]
    water = params["saturation"]
    coarse = np.log(params["grain_size"] / 0.05) / np.log(40.0)
    fines = params["silt"] + 2.0 * params["clay"]
    base = 0.62 - 0.12 * water - 0.08 * coarse + 0.3 * fines
    edge = 0.5 * (1 - np.tanh(2.0 * wl))  # absorption edge of iron oxide in the blue-green
    return np.clip(base * (1 - 0.55 * iron * edge) + 0.03 * wl, 0.01, 0.99)


#: How much darker the fake engine is with path memory (as memory darkens bright fines-rich sand).
MEMORY_FACTOR = 0.9


def fake_reflectance(params, wavelengths_nm, *, rays, seed, memory="none"):
    truth = true_reflectance(params, wavelengths_nm) * (1.0 if memory == "none" else MEMORY_FACTOR)
    stderr = np.sqrt(truth * (1 - truth) / rays)
    values = truth + stderr * np.random.default_rng(seed).standard_normal(truth.shape)
    return SimpleNamespace(values=values, stderr=stderr, wavelengths=np.asarray(wavelengths_nm, dtype=float))


def fail_once(marker_dir, fail_index_seed, params, wavelengths_nm, *, rays, seed):
    """fake_reflectance, but the first attempt at the sample with engine seed
    ``fail_index_seed`` raises (as a worker crash would)."""
    if seed == fail_index_seed:
        marker = Path(marker_dir) / "failed-once"
        try:
            os.close(os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            pass
        else:
            raise RuntimeError("simulated worker failure")
    return fake_reflectance(params, wavelengths_nm, rays=rays, seed=seed)
