"""The "Refine with Monte Carlo" job: the engine's spectrum of a sample with its standard errors.

The request gives the sample, the rays per wavelength (≤ `Limits.max_rays`), the wavelengths
(default 350–2500 nm every 50 nm, ≤ `Limits.max_wavelengths`) and a seed. The job runs
`sandlight.reflectance` (spectral path sharing, all cores) and answers the spectrum, the standard
error band √(ρ(1 − ρ)/N) (with sharing: from the per-ray weights) and, since the spectrum
covers 400–700 nm, the colour of the Monte Carlo spectrum.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from sandlight.checks import check_count, check_seed, check_wavelengths
from sandlight.engine import reflectance
from sandlight.errors import ParameterError
from sandlight.sample import SandSample
from sandlight.web.jobs import JobContext
from sandlight.web.limits import Limits
from sandlight.web.spectra import colour_of

__all__ = ["DEFAULT_WAVELENGTHS_NM", "DEFAULT_RAYS", "reflectance_work"]

#: The default grid of a job: 350–2500 nm every 50 nm (44 wavelengths).
DEFAULT_WAVELENGTHS_NM = tuple(float(x) for x in np.arange(350.0, 2501.0, 50.0))
#: Default rays per wavelength (standard error ≤ 0.005).
DEFAULT_RAYS = 10_000


def reflectance_work(
    sample: SandSample, body: dict[str, Any], limits: Limits
) -> Callable[[JobContext], dict[str, Any]]:
    """The job's work for a request ``body`` (its ``rays``, ``wavelengths_nm``, ``seed``), checked
    now, before the job is queued.

    Raises
    ------
    ParameterError
        Rays not a count or over the limit, wavelengths outside 350–2500 nm or too many, a bad seed.
    """
    rays = check_count("rays", body.get("rays", DEFAULT_RAYS))
    if rays > limits.max_rays:
        raise ParameterError("rays", rays, f"at most {limits.max_rays:,} rays per wavelength on this server")
    wl = check_wavelengths("wavelengths_nm", body.get("wavelengths_nm", DEFAULT_WAVELENGTHS_NM))
    if wl.size > limits.max_wavelengths:
        raise ParameterError("wavelengths_nm", f"{wl.size} wavelengths", f"at most {limits.max_wavelengths}")
    if np.any(np.diff(wl) <= 0):
        raise ParameterError("wavelengths_nm", wl.tolist(), "strictly increasing wavelengths")
    seed = check_seed("seed", body.get("seed", 0))

    def work(context: JobContext) -> dict[str, Any]:
        result = reflectance(sample, wl, rays=rays, seed=seed, progress=True)
        answer: dict[str, Any] = {
            "wavelengths_nm": result.wavelengths.tolist(),
            "reflectance": result.values.tolist(),
            "stderr": result.stderr.tolist(),
            "rays": rays,
            "seed": seed,
            "elapsed_s": result.elapsed_s,
            "colour": colour_of(result.wavelengths, result.values) if wl[0] <= 400 and wl[-1] >= 700 else None,
            "_keep": result,
        }
        return answer

    return work
