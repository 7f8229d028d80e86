"""Optical constants with calibrated k: the shipped tables, with the k of some minerals replaced by
their calibration output (a ``<mineral>-k.csv`` of :func:`sandlight.calibration.write_k_table`).

The shipped tables already hold the calibrated k of the quartz host and goethite
(docs/optical-constants.md); this is for what-if runs with another calibration output (another
mineral, another calibration setting): pass the result as ``optical_constants`` to
:class:`sandlight.physics.media.SandMedium`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from sandlight.calibration.report import read_k_table
from sandlight.errors import ModelFileError
from sandlight.optics import complex_index, interpolate_k
from sandlight.physics.medium import OpticalConstants

__all__ = ["with_calibrated_k"]


def with_calibrated_k(
    tables: Mapping[str, str | os.PathLike[str]], base: OpticalConstants = complex_index
) -> OpticalConstants:
    """``base`` with each mineral's k from its calibrated k table.

    Parameters
    ----------
    tables : mapping of str to path
        Mineral name → its ``<mineral>-k.csv`` (e.g. ``docs/calibration/quartz/quartz-k.csv``); the
        table's ``material`` must be that mineral.
    base : callable
        ``(material, wavelength_nm) -> n + ik`` giving n, and k for the other materials.

    Returns
    -------
    callable
        ``(material, wavelength_nm) -> n + ik``: n from ``base``, k interpolated log-linearly in
        the table (the rule of :func:`sandlight.optics.interpolate_k`) for the minerals given.

    Raises
    ------
    ModelFileError
        A file that is not a calibrated k table, or one of another mineral.
    """
    k_of = {}
    for mineral, path in tables.items():
        header, wavelength_nm, _, k = read_k_table(path)
        if header.get("material") != mineral:
            raise ModelFileError(f"{path}: a calibrated k table of {header.get('material')!r}, not of {mineral!r}")
        k_of[mineral] = (wavelength_nm, k)

    def index(material: str, wavelength_nm: float) -> complex:
        m = complex(base(material, wavelength_nm))
        if material not in k_of:
            return m
        wl, k = k_of[material]
        return complex(m.real, float(np.asarray(interpolate_k(wavelength_nm, wl, k)).reshape(-1)[0]))

    return index
