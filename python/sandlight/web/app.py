"""The explorer's ASGI application: `create_app` puts the routes, the middleware and the error
answers together (see docs/explorer.md for the API it serves)."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator, Sequence

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.routing import Route

from sandlight.web import assets, preview, routes, spectra
from sandlight.web.batching import Batcher
from sandlight.web.errors import EXCEPTION_HANDLERS
from sandlight.web.jobs import JobManager
from sandlight.web.limits import Limits
from sandlight.web.security import BodyLimit, SameOrigin, SecurityHeaders

__all__ = ["create_app", "LOCAL_HOSTS", "UPLOAD_PATH"]

#: The host names a server bound to the loopback interface answers for.
LOCAL_HOSTS = ("127.0.0.1", "localhost", "[::1]", "::1")
#: The one route that takes an upload (its body limit is `Limits.max_upload_bytes`).
UPLOAD_PATH = "/api/measured"

ROUTES = [
    Route("/", assets.index, methods=["GET"]),
    Route("/static/{name}", assets.asset, methods=["GET"]),
    Route("/api/schema", routes.schema, methods=["GET"]),
    Route("/api/validate", routes.validate, methods=["POST"]),
    Route("/api/spectrum", routes.spectrum, methods=["POST"]),
    Route("/api/colour", routes.colour, methods=["POST"]),
    Route("/api/brdf", routes.brdf, methods=["POST"]),
    Route(UPLOAD_PATH, routes.measured, methods=["POST"]),
    Route("/api/export/{name}", routes.export, methods=["POST"]),
    Route("/api/jobs/{kind}", routes.start_job, methods=["POST"]),
    Route("/api/jobs/{id}", routes.job_status, methods=["GET"]),
    Route("/api/jobs/{id}", routes.cancel_job, methods=["DELETE"]),
    Route("/api/jobs/{id}/events", routes.job_events, methods=["GET"]),
]


def create_app(limits: Limits = Limits(), *, allowed_hosts: Sequence[str] | None = LOCAL_HOSTS) -> Starlette:
    """The explorer as a Starlette application.

    Parameters
    ----------
    limits : Limits
        Bounds on requests, uploads, rays, images and jobs.
    allowed_hosts : sequence of str or None
        Host names answered (``Host`` header); the default serves only the loopback names
        (a test client must use one, e.g. ``base_url="http://127.0.0.1"``). None answers any host (a server
        made reachable from other machines with ``--allow-remote``).

    Returns
    -------
    starlette.applications.Starlette
        ``app.state.jobs`` is its `JobManager`, ``app.state.limits`` its limits; the spectrum
        and colour requests waiting at one moment are answered together
        (``app.state.spectrum_batcher``, ``app.state.colour_batcher``: `sandlight.web.batching`).
    """

    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        # Load the models and warm the preview's caches before the first request.
        spectra.bank()
        await run_in_threadpool(preview.warm_up)
        try:
            yield
        finally:
            app.state.jobs.shutdown()

    def body_limit(path: str) -> int:
        return limits.max_upload_bytes if path == UPLOAD_PATH else limits.max_body_bytes

    middleware = [
        Middleware(SecurityHeaders),
        Middleware(TrustedHostMiddleware, allowed_hosts=["*"] if allowed_hosts is None else list(allowed_hosts)),
        Middleware(SameOrigin),
        Middleware(BodyLimit, limit_for=body_limit),
    ]
    app = Starlette(routes=ROUTES, middleware=middleware, exception_handlers=EXCEPTION_HANDLERS, lifespan=lifespan)
    app.state.limits = limits
    app.state.spectrum_batcher = Batcher(spectra.spectrum_answers)
    app.state.colour_batcher = Batcher(spectra.colour_answers)
    app.state.jobs = JobManager(limits.max_running_jobs, limits.max_jobs_per_client, limits.max_kept_jobs)
    return app
