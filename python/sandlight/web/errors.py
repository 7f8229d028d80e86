"""Every refusal of the explorer as one JSON answer; no traceback ever reaches a client.

A user's mistake is a 4xx answer whose body names what was wrong, with the same words the Python
API uses (`sandlight.errors.ParameterError`: parameter, value, what is allowed)::

    {"error": "parameter", "parameter": "iron_oxide", "value": "0.5",
     "allowed": "a real number in [0, 0.1]", "message": "iron_oxide = 0.5 is not allowed: ..."}

Only a bug in sandlight gives 500, with a generic message; the traceback goes to the server's log.
"""

from __future__ import annotations

import logging

from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import JSONResponse

from sandlight.errors import ModelFileError, ParameterError, SandlightError, quoted

__all__ = ["ApiError", "EXCEPTION_HANDLERS", "INTERNAL_MESSAGE"]

log = logging.getLogger("sandlight.web")

#: What a client is told of an internal error (the details are logged on the server only).
INTERNAL_MESSAGE = "internal error in sandlight (the server's log has the details); please report it"


class ApiError(SandlightError):
    """A refusal that is not about one parameter: a limit, a missing job, a wrong content type.

    Parameters
    ----------
    status : int
        The HTTP status (4xx).
    kind : str
        The ``error`` field of the answer (``"limit"``, ``"not-found"``, ``"content-type"`` …).
    message : str
        One readable sentence saying what was refused and what is allowed.
    """

    def __init__(self, status: int, kind: str, message: str) -> None:
        super().__init__(message)
        self.status, self.kind, self.message = status, kind, message


def parameter_body(exc: ParameterError) -> dict:
    """The JSON body of a `ParameterError`: its name, value (quoted, shortened), allowed values."""
    return {
        "error": "parameter",
        "parameter": str(exc.name),
        "value": quoted(exc.value),
        "allowed": exc.allowed,
        "message": str(exc),
    }


async def _parameter_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, ParameterError)
    return JSONResponse(parameter_body(exc), status_code=400)


async def _file_error(request: Request, exc: Exception) -> JSONResponse:
    # Raised on an uploaded file that is not a spectrum (the message names the line).
    return JSONResponse({"error": "file", "message": str(exc)}, status_code=422)


async def _api_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, ApiError)
    return JSONResponse({"error": exc.kind, "message": exc.message}, status_code=exc.status)


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, HTTPException)
    return JSONResponse({"error": "http", "message": str(exc.detail)}, status_code=exc.status_code)


async def _internal_error(request: Request, exc: Exception) -> JSONResponse:
    log.error("internal error on %s %s", request.method, request.url.path, exc_info=exc)
    return JSONResponse({"error": "internal", "message": INTERNAL_MESSAGE}, status_code=500)


#: Starlette's exception handlers: the most specific class first.
EXCEPTION_HANDLERS = {
    ParameterError: _parameter_error,
    ModelFileError: _file_error,
    ApiError: _api_error,
    HTTPException: _http_error,
    Exception: _internal_error,
}
