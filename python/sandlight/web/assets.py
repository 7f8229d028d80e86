"""The page's static files: a fixed list shipped inside the package (``sandlight/web/static``).

Only these names are served, read from the package's resources; a request's path is looked up in
this table and never reaches the file system. No CDN, no build step: plain HTML, CSS and one
JavaScript module drawn with SVG and canvas, so the page works offline.
"""

from __future__ import annotations

import functools
from importlib import resources

from starlette.requests import Request
from starlette.responses import Response

from sandlight.web.errors import ApiError

__all__ = ["ASSETS", "asset_response"]

#: The files served, by name, and their media types.
ASSETS = {
    "index.html": "text/html; charset=utf-8",
    "explorer.js": "text/javascript; charset=utf-8",
    "explorer.css": "text/css; charset=utf-8",
}


@functools.cache
def _read(name: str) -> bytes:
    return (resources.files("sandlight.web") / "static" / name).read_bytes()


def asset_response(name: str) -> Response:
    """The asset called ``name``; 404 for any other name."""
    if name not in ASSETS:
        raise ApiError(404, "not-found", f"no page asset {name!r}")
    return Response(_read(name), media_type=ASSETS[name])


async def index(request: Request) -> Response:
    """``GET /``: the explorer page."""
    return asset_response("index.html")


async def asset(request: Request) -> Response:
    """``GET /static/{name}``: one of `ASSETS`."""
    return asset_response(request.path_params["name"])
