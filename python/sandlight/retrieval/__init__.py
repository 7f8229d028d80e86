"""Retrieval: sample parameters from a measured spectrum, with honest uncertainty (issue 20).

Public objects
--------------
fit
    :func:`sandlight.retrieval.retrieve.fit` (also ``sandlight.fit``).
FitResult
    Its result (:mod:`sandlight.retrieval.result`).
bands, load_sensor, SpectralResponse
    Sensor bands (:mod:`sandlight.retrieval.sensors`; also ``sandlight.bands``).
BandMask
    Wavelength intervals left out (:mod:`sandlight.retrieval.mask`).
NotIdentifiableError
    An interval asked of a parameter the data do not constrain.

See docs/retrieval.md for the method, its assumptions and the recovery study.
"""

from sandlight.retrieval.identifiability import NotIdentifiableError
from sandlight.retrieval.mask import BandMask
from sandlight.retrieval.result import FitResult
from sandlight.retrieval.retrieve import fit
from sandlight.retrieval.sensors import SpectralResponse, bands, load_sensor

__all__ = ["fit", "FitResult", "bands", "load_sensor", "SpectralResponse", "BandMask", "NotIdentifiableError"]
