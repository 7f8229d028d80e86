"""The pure end-member powders of the calibration and their measured spectra (issue 17 §1).

Public objects
--------------
EndMember
    One measured powder: mineral, USGS spectrum, grain sizes and what its description says.
end_members
    The inventory (``sandlight/data/calibration/end_members.toml``), optionally one mineral's.
MEASUREMENT_SIGMA
    Assumed standard error of a measured absolute reflectance.
measured_reflectance
    An end-member's measured reflectance at given wavelengths, with its standard error.

The inventory is data: every value in it is taken from the sample's USGS description, which
its comments quote, or is a default the comments give and justify.
"""

from __future__ import annotations

import functools
import math
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from importlib import resources

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ModelFileError, ParameterError
from sandlight.optics import MATERIALS

__all__ = ["EndMember", "end_members", "MEASUREMENT_SIGMA", "measured_reflectance"]

#: Standard error of a measured absolute reflectance (fraction). splib07a gives no per-channel
#: error; this is an assumed accuracy of the Beckman absolute reflectance scale (Kokaly et al.
#: 2017 calibrate it against a Spectralon standard of known absolute reflectance), larger than
#: the channel-to-channel noise (0.0003-0.002 for these powders, from second differences of
#: neighbouring Beckman channels).
MEASUREMENT_SIGMA = 0.005

_FIELDS = {
    "id": str,
    "mineral": str,
    "spectrum": str,
    "series": str,
    "size_um": list,
    "size_basis": str,
    "purity": str,
    "impurities": str,
    "use_in_fit": bool,
    "excluded_because": str,
}
_SIZE_BASES = ("sieve", "sieve, open", "microscope", "default")


@dataclass(frozen=True)
class EndMember:
    """One measured pure powder.

    Attributes
    ----------
    id : str
        Short name used in reports, e.g. ``"GDS69.a"``.
    mineral : str
        The material of :data:`sandlight.optics.MATERIALS` whose k this sample calibrates.
    spectrum : str
        splib07a file stem, for :func:`sandlight.measured.usgs_library`.
    series : str
        Name of the grain-size series (samples of one rock), ``""`` for none.
    size_um : tuple[float, float]
        (d_min, d_max), volume-equivalent diameters in µm: equal mass per log-size interval
        between them.
    size_basis : str
        ``"sieve"``, ``"sieve, open"``, ``"microscope"`` or ``"default"`` (see the inventory's
        header).
    purity : str
        USGS spectral purity code for 0.2–3 µm (``""`` when the record does not give it).
    impurities : str
        Other phases the description names.
    use_in_fit : bool
        False for records that are not a pure powder of the mineral.
    excluded_because : str
        Why, when ``use_in_fit`` is False.
    """

    id: str
    mineral: str
    spectrum: str
    series: str
    size_um: tuple[float, float]
    size_basis: str
    purity: str
    impurities: str
    use_in_fit: bool
    excluded_because: str


def _parse(entry: dict, where: str) -> EndMember:
    problems = [f"missing {key!r}" for key in _FIELDS if key not in entry]
    problems += [f"unknown field {key!r}" for key in entry if key not in _FIELDS]
    problems += [
        f"{key!r} must be {kind.__name__}"
        for key, kind in _FIELDS.items()
        if key in entry and not isinstance(entry[key], kind)
    ]
    if problems:
        raise ModelFileError(f"{where}: " + "; ".join(problems))
    size = entry["size_um"]
    if not (
        len(size) == 2 and all(isinstance(d, (int, float)) and math.isfinite(d) for d in size) and 0 < size[0] < size[1]
    ):
        raise ModelFileError(f"{where}: size_um = {size!r} must be [d_min, d_max] with 0 < d_min < d_max (µm)")
    if entry["mineral"] not in MATERIALS:
        raise ModelFileError(f"{where}: mineral {entry['mineral']!r} is not one of {', '.join(MATERIALS)}")
    if entry["size_basis"] not in _SIZE_BASES:
        raise ModelFileError(f"{where}: size_basis {entry['size_basis']!r} is not one of {', '.join(_SIZE_BASES)}")
    if not entry["use_in_fit"] and not entry["excluded_because"]:
        raise ModelFileError(f"{where}: an excluded end-member must say why (excluded_because)")
    return EndMember(**{**entry, "size_um": (float(size[0]), float(size[1]))})


@functools.cache
def _inventory() -> tuple[EndMember, ...]:
    name = "sandlight/data/calibration/end_members.toml"
    resource = resources.files("sandlight").joinpath("data", "calibration", "end_members.toml")
    try:
        data = tomllib.loads(resource.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ModelFileError(f"{name}: end-member inventory missing from the installed package") from None
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(f"{name}: not valid TOML: {exc}") from None
    members = tuple(_parse(e, f"{name}, end_member {i + 1}") for i, e in enumerate(data.get("end_member", [])))
    ids = [m.id for m in members]
    duplicates = sorted({i for i in ids if ids.count(i) > 1})
    if duplicates:
        raise ModelFileError(f"{name}: duplicate ids {', '.join(duplicates)}")
    return members


def end_members(
    mineral: str | None = None, *, fit_only: bool = False, ids: Iterable[str] | None = None
) -> tuple[EndMember, ...]:
    """The end-member inventory.

    Parameters
    ----------
    mineral : str or None
        Keep only this material's records (a name of :data:`sandlight.optics.MATERIALS` that the
        inventory has); None for all.
    fit_only : bool
        Keep only the records with ``use_in_fit``.
    ids : iterable of str or None
        Keep only these ids, in this order (each must exist).

    Returns
    -------
    tuple of EndMember

    Raises
    ------
    sandlight.errors.ParameterError
        An unknown ``mineral`` or id.
    """
    members = _inventory()
    if mineral is not None:
        minerals = sorted({m.mineral for m in members})
        if mineral not in minerals:
            raise ParameterError("mineral", mineral, "one of " + ", ".join(minerals))
        members = tuple(m for m in members if m.mineral == mineral)
    if fit_only:
        members = tuple(m for m in members if m.use_in_fit)
    if ids is not None:
        by_id = {m.id: m for m in members}
        ids = list(ids)
        unknown = [i for i in ids if i not in by_id]
        if unknown:
            raise ParameterError("ids", unknown, "ids of the selected end-members: " + ", ".join(by_id))
        members = tuple(by_id[i] for i in ids)
    return members


def measured_reflectance(member: EndMember, wavelengths_nm: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """An end-member's measured reflectance at model wavelengths.

    Parameters
    ----------
    member : EndMember
    wavelengths_nm : array_like
        Vacuum wavelengths λ in nm.

    Returns
    -------
    values, sigma : numpy.ndarray
        Directional-hemispherical reflectance (fraction, NaN where the library has no usable
        channel) brought to the wavelengths as :func:`sandlight.validation.measured_on_grid`
        does, and its standard error :data:`MEASUREMENT_SIGMA` (NaN where the value is).
    """
    from sandlight.measured import read_usgs, usgs_library
    from sandlight.validation import measured_on_grid

    values = measured_on_grid(read_usgs(usgs_library(member.spectrum)), wavelengths_nm)
    return values, np.where(np.isfinite(values), MEASUREMENT_SIGMA, np.nan)
