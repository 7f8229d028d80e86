"""The bounds of the explorer: what one request, upload, job or image may ask for.

A local server still meets careless or hostile input (a page in another tab, a script in a loop);
every bound below is checked before the work starts, and a request over it is refused with a
4xx answer naming the bound (sandlight.web.errors).
"""

from __future__ import annotations

from dataclasses import dataclass

from sandlight.checks import check_whole_number


@dataclass(frozen=True)
class Limits:
    """Bounds on requests and work (all checked before any work is done).

    Attributes
    ----------
    max_body_bytes : int
        Largest JSON request body, bytes (a full sample with its comparison is about 1 kB).
    max_upload_bytes : int
        Largest uploaded measured spectrum, bytes (a splib07 Beckman file is about 10 kB, an ASD
        FieldSpec file about 40 kB).
    max_rays : int
        Most rays per wavelength of a Monte Carlo job (10⁵ rays: standard error ≤ 0.0016).
    max_wavelengths : int
        Most wavelengths of a Monte Carlo job (350–2500 nm every 10 nm is 216).
    max_preview_px : int
        Longest side of a preview image, pixels.
    max_polar_points : int
        Most directions of a BRDF polar map (n_theta × n_phi).
    max_jobs_per_client : int
        Unfinished jobs (queued or running) one client address may have at a time.
    max_running_jobs : int
        Jobs running at once over all clients (the others wait in a queue).
    max_kept_jobs : int
        Finished jobs whose results are kept for reading and export (oldest dropped first).
    """

    max_body_bytes: int = 64 * 1024
    max_upload_bytes: int = 1024 * 1024
    max_rays: int = 100_000
    max_wavelengths: int = 216
    max_preview_px: int = 256
    max_polar_points: int = 100 * 180
    max_jobs_per_client: int = 2
    max_running_jobs: int = 1
    max_kept_jobs: int = 32

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            check_whole_number(name, value, 1)
