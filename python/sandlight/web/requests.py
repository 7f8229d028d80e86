"""Reading what a request asks for: its JSON body, the sample in it, and its numbers.

Every value is checked with the checks the Python API uses, so that the explorer refuses what
`SandSample` and the engine refuse, in the same words (a `ParameterError`).
"""

from __future__ import annotations

import json
import math
from typing import Any

from starlette.requests import Request

from sandlight.checks import check_real
from sandlight.errors import ParameterError
from sandlight.sample import SandSample
from sandlight.web.errors import ApiError

__all__ = ["json_body", "sample_in", "number_in", "keys_allowed"]


async def json_body(request: Request) -> dict[str, Any]:
    """The request's body as a JSON object.

    The body must be sent as ``application/json`` (which a page of another site cannot send
    without the server's consent, CORS) and hold one JSON object; NaN and infinities are refused
    (strict JSON).

    Raises
    ------
    ApiError
        415 for another content type.
    ParameterError
        The body is not JSON or not an object (parameter ``body``).
    """
    kind = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if kind != "application/json":
        raise ApiError(415, "content-type", f"send the request body as application/json, not {kind or 'nothing'!r}")
    raw = await request.body()
    if not raw.strip():
        return {}
    try:
        doc = json.loads(raw.decode("utf-8"), parse_constant=_refuse_constant)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ParameterError("body", raw[:80].decode("utf-8", "replace"), f"a JSON object ({exc})") from None
    if not isinstance(doc, dict):
        raise ParameterError("body", doc, "a JSON object (name: value, …)")
    return doc


def _refuse_constant(name: str) -> float:
    raise json.JSONDecodeError(f"{name} is not strict JSON", name, 0)


def keys_allowed(body: dict[str, Any], allowed: tuple[str, ...]) -> None:
    """Refuse a key of ``body`` that is not in ``allowed`` (a typo must not be silently ignored)."""
    for key, value in body.items():
        if key not in allowed:
            raise ParameterError(str(key), value, "not a field of this request; allowed: " + ", ".join(allowed))


def sample_in(body: dict[str, Any], key: str = "sample") -> SandSample:
    """The sample under ``key``: a table of parameters (``{"preset": "red-dune", "iron_oxide": 0.02}``),
    a preset name, or absent (the default sample). An error in a sample other than ``"sample"``
    names the parameter with the key in front (``compare.iron_oxide``).

    Raises
    ------
    ParameterError
        From `SandSample.from_dict`: an unknown parameter, a value out of its domain, a wrong
        type, inconsistent separates, an unknown preset.
    """
    value = body.get(key, {})
    if not isinstance(value, (str, dict)):
        raise ParameterError(key, value, "a table of sample parameters (with an optional 'preset') or a preset name")
    try:
        return SandSample.preset(value) if isinstance(value, str) else SandSample.from_dict(value)
    except ParameterError as exc:
        if key == "sample":
            raise
        # Another sample of the request (the comparison B): say which one is wrong.
        raise ParameterError(f"{key}.{exc.name}", exc.value, exc.allowed) from None


def number_in(body: dict[str, Any], key: str, default: float, low: float, high: float) -> float:
    """The number under ``key`` (``default`` when absent), checked to lie in [low, high]."""
    value = body.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ParameterError(key, value, f"a number in [{low:g}, {high:g}]")
    return check_real(key, value, low, high)
