"""The HTTP handlers of the explorer's JSON API (docs/explorer.md documents each).

Handlers are thin: they read the request (`sandlight.web.requests`), call the module that knows
the answer, and return JSON. Work longer than a few milliseconds runs in a thread (Starlette's
threadpool), long work in a job (`sandlight.web.jobs`).
"""

from __future__ import annotations

import json
import math
from typing import Any

from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import JSONResponse, Response, StreamingResponse

from sandlight.checks import check_whole_number
from sandlight.engine import ReflectanceResult
from sandlight.errors import ParameterError
from sandlight.sample import PARAMETERS, SandSample
from sandlight.web import brdf_maps, exports, measured_upload, preview, refine, spectra
from sandlight.web.errors import ApiError
from sandlight.web.jobs import JobManager
from sandlight.web.limits import Limits
from sandlight.web.requests import json_body, keys_allowed, number_in, sample_in

__all__ = [
    "schema",
    "validate",
    "spectrum",
    "colour",
    "brdf",
    "measured",
    "export",
    "start_job",
    "job_status",
    "job_events",
    "cancel_job",
]


def _jobs(request: Request) -> JobManager:
    return request.app.state.jobs


def _limits(request: Request) -> Limits:
    return request.app.state.limits


def _json_number(x: float | None) -> float | str | None:
    return "inf" if x == math.inf else x


def _parameter(p: Any) -> dict[str, Any]:
    return {
        "name": p.name,
        "unit": p.unit,
        "default": _json_number(p.default),
        "low": p.low,
        "high": _json_number(p.high),
        "low_open": p.low_open,
        "kind": p.kind,
        "choices": list(p.choices),
        "description": p.description,
        "allowed": p.allowed,
    }


async def schema(request: Request) -> JSONResponse:
    """``GET /api/schema``: parameters (unit, domain, default), presets, models, limits."""
    bank = spectra.bank()
    limits = _limits(request)
    return JSONResponse(
        {
            "parameters": [_parameter(p) for p in PARAMETERS],
            "presets": {name: SandSample.preset(name).to_dict() for name in SandSample.presets()},
            "models": [
                {"name": m.name_, "description": bank.describe(m.name_), "holdout_rms": spectra.holdout_rms(m)}
                for m in bank.models
            ],
            "model_wavelengths_nm": bank.wavelengths_.tolist(),
            "engine_range_nm": list(spectra.ENGINE_RANGE_NM),
            "refine_defaults": {"rays": refine.DEFAULT_RAYS, "wavelengths_nm": list(refine.DEFAULT_WAVELENGTHS_NM)},
            "limits": dict(limits.__dict__),
            "exports": list(exports.EXPORTS),
            "preview": preview.PREVIEW_OPTIONS,
        }
    )


async def validate(request: Request) -> JSONResponse:
    """``POST /api/validate``: the full, checked sample (400 naming the parameter otherwise)."""
    body = await json_body(request)
    keys_allowed(body, ("sample",))
    sample = sample_in(body)
    return JSONResponse({"valid": True, "sample": sample.to_dict()})


async def spectrum(request: Request) -> JSONResponse:
    """``POST /api/spectrum``: the predicted spectrum, the model and its hold-out error."""
    body = await json_body(request)
    keys_allowed(body, ("sample",))
    return JSONResponse(await request.app.state.spectrum_batcher(sample_in(body)))


async def colour(request: Request) -> JSONResponse:
    """``POST /api/colour``: sRGB and CIELAB (D50, D65) of A, and of B with ΔE2000."""
    body = await json_body(request)
    keys_allowed(body, ("sample", "compare"))
    compare = sample_in(body, "compare") if body.get("compare") is not None else None
    return JSONResponse(await request.app.state.colour_batcher((sample_in(body), compare)))


def _grid_size(body: dict, name: str, default: int, low: int, high: int) -> int:
    return check_whole_number(name, body.get(name, default), low, high)


async def brdf(request: Request) -> JSONResponse:
    """``POST /api/brdf``: polar map and principal plane at an incidence and wavelength."""
    body = await json_body(request)
    keys_allowed(body, ("sample", "incidence_deg", "wavelength_nm", "n_theta", "n_phi"))
    sample = sample_in(body)
    incidence = number_in(body, "incidence_deg", 30.0, 0.0, 89.0)
    wavelength = number_in(body, "wavelength_nm", 550.0, 350.0, 2500.0)
    n_theta = _grid_size(body, "n_theta", 30, 2, 100)
    n_phi = _grid_size(body, "n_phi", 72, 4, 180)
    if n_theta * n_phi > _limits(request).max_polar_points:
        raise ParameterError("n_theta × n_phi", n_theta * n_phi, f"at most {_limits(request).max_polar_points}")
    answer = await run_in_threadpool(brdf_maps.brdf_answer, sample, incidence, wavelength, n_theta, n_phi)
    return JSONResponse(answer)


async def measured(request: Request) -> JSONResponse:
    """``POST /api/measured`` (multipart form: ``file``, optional ``sample`` as JSON text and
    ``format``): the uploaded spectrum and its RMS against the model of the sample."""
    limit = _limits(request).max_upload_bytes
    async with request.form(max_files=1, max_fields=3, max_part_size=limit) as form:
        upload = form.get("file")
        if upload is None or isinstance(upload, str):
            raise ParameterError("file", None if upload is None else "text", "an uploaded file (form field 'file')")
        data = await upload.read(limit + 1)
        if len(data) > limit:
            raise ApiError(413, "limit", f"the uploaded file is larger than the limit of {limit:,} bytes")
        text = form.get("sample", "{}")
        try:
            body = {"sample": json.loads(text) if isinstance(text, str) else None}
        except json.JSONDecodeError as exc:
            raise ParameterError("sample", text, f"a JSON table of sample parameters ({exc})") from None
        sample = sample_in(body)
        form_name = form.get("format", "auto")
        name = upload.filename or "the upload"
    spectrum = await run_in_threadpool(measured_upload.read_upload, data, name, form_name)
    return JSONResponse(measured_upload.overlay_answer(spectrum, spectra.predict(sample)))


def _job_result(request: Request, body: dict) -> ReflectanceResult | None:
    if body.get("job") is None:
        return None
    job = _jobs(request).get(str(body["job"]))
    if job.state != "done" or job.kind != "reflectance":
        raise ParameterError("job", body["job"], "a finished Monte Carlo reflectance job")
    return job.result["_keep"]


async def export(request: Request) -> Response:
    """``POST /api/export/{name}``: the sample, spectrum or BRDF table as a file."""
    name = request.path_params["name"]
    if name not in exports.EXPORTS:
        raise ParameterError("export", name, "one of " + ", ".join(exports.EXPORTS))
    body = await json_body(request)
    keys_allowed(body, ("sample", "job", "n_mu", "n_dphi"))
    sample = sample_in(body)
    suffix = "." + name.rsplit(".", 1)[1]
    if name == "sample.toml":
        content = exports.sample_toml(sample)
    elif name == "brdf.nc":
        n_mu, n_dphi = _grid_size(body, "n_mu", 16, 2, 64), _grid_size(body, "n_dphi", 16, 2, 64)
        content = await run_in_threadpool(exports.brdf_table_file, sample, n_mu, n_dphi)
    elif (result := _job_result(request, body)) is not None:
        content = await run_in_threadpool(exports.reflectance_file, result, suffix)
    else:
        prediction = spectra.predict(sample)
        if not prediction.covered:
            raise ParameterError("sample", "outside every model's domain", prediction.description)
        content = await run_in_threadpool(exports.prediction_file, sample, prediction, suffix)
    disposition = f'attachment; filename="sandlight-{name}"'
    return Response(content, media_type=exports.EXPORTS[name], headers={"content-disposition": disposition})


async def start_job(request: Request) -> JSONResponse:
    """``POST /api/jobs/{kind}`` (reflectance, preview): 202 with the job's id and URLs."""
    kind = request.path_params["kind"]
    if kind not in ("reflectance", "preview"):
        raise ParameterError("job kind", kind, "one of 'reflectance', 'preview'")
    body = await json_body(request)
    limits = _limits(request)
    if kind == "reflectance":
        keys_allowed(body, ("sample", "rays", "wavelengths_nm", "seed"))
        work = refine.reflectance_work(sample_in(body), body, limits)
    else:
        keys_allowed(body, ("sample", *preview.PREVIEW_OPTIONS))
        work = preview.preview_work(sample_in(body), body, limits)
    client = request.client.host if request.client else "unknown"
    job = _jobs(request).submit(kind, client, work)
    return JSONResponse(
        {"id": job.id, "state": job.state, "status": f"/api/jobs/{job.id}", "events": f"/api/jobs/{job.id}/events"},
        status_code=202,
    )


async def job_status(request: Request) -> JSONResponse:
    """``GET /api/jobs/{id}``: state, progress, result."""
    return JSONResponse(_jobs(request).get(request.path_params["id"]).status())


async def job_events(request: Request) -> StreamingResponse:
    """``GET /api/jobs/{id}/events``: server-sent events until the job finishes."""
    jobs = _jobs(request)
    job = jobs.get(request.path_params["id"])
    return StreamingResponse(jobs.events(job), media_type="text/event-stream", headers={"x-accel-buffering": "no"})


async def cancel_job(request: Request) -> JSONResponse:
    """``DELETE /api/jobs/{id}``: cancel (202; the state turns 'cancelled' within a batch)."""
    job = _jobs(request).cancel(request.path_params["id"])
    return JSONResponse({"id": job.id, "state": job.state, "cancel_requested": True}, status_code=202)
