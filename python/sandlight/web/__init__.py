"""The sand explorer (``sandlight serve``): a local web application over a documented JSON API.

The page (``static/``) is one client of the API; scripts can be others (docs/explorer.md lists
every endpoint, its request, its response and its errors). Modules, one concept each:

- :mod:`~sandlight.web.app`: `create_app`, the Starlette application (routes, middleware, errors).
- :mod:`~sandlight.web.server`: running it with uvicorn on 127.0.0.1 (another host only when asked).
- :mod:`~sandlight.web.limits`: `Limits`, the bounds on requests, uploads, rays, images and jobs.
- :mod:`~sandlight.web.security`: security headers, the request-size limit, host and origin checks.
- :mod:`~sandlight.web.errors`: every refusal as a JSON answer naming the parameter; no tracebacks.
- :mod:`~sandlight.web.requests`: reading a request's JSON body and its sample.
- :mod:`~sandlight.web.spectra`: the predicted spectrum of a sample and the colour of a spectrum.
- :mod:`~sandlight.web.brdf_maps`: the BRDF at one incidence and wavelength (polar map, principal plane).
- :mod:`~sandlight.web.measured_upload`: an uploaded measured spectrum and its RMS against the model.
- :mod:`~sandlight.web.exports`: the sample, the spectrum and the BRDF table as files.
- :mod:`~sandlight.web.jobs`: background jobs with bounded concurrency, progress events and cancel.
- :mod:`~sandlight.web.preview`: the small rendered view of the sand, refined progressively.
- :mod:`~sandlight.web.routes`: the HTTP handlers.
- :mod:`~sandlight.web.assets`: the page's static files, a fixed list shipped in the package.
"""

from sandlight.web.app import create_app
from sandlight.web.limits import Limits

__all__ = ["create_app", "Limits"]
