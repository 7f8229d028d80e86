"""CIE XYZ → sRGB (two modes) and CIELAB.

Public objects
--------------
- :data:`MODES`: ``"managed"`` (default) and ``"paper"``.
- :data:`PAPER_XYZ_TO_LINEAR_RGB`: the matrix printed in §4.1.1 of the paper.
- :func:`paper_encoding`: the paper's gamma, 1.055·v^(1/2.4) − 0.055, as printed.
- :func:`xyz_to_srgb`: encoded sRGB in [0, 1], optionally with an out-of-gamut flag.
- :func:`xyz_to_lab`: CIELAB relative to the white of the illuminant and observer.
- :func:`srgb_to_uint8`: 8-bit code values.

The two modes
-------------
``paper`` reproduces §4.1.1 exactly: the printed XYZ → linear-RGB matrix (the IEC 61966-2-1
sRGB matrix, which assumes a D65 white) is applied *directly* to the D50 tristimulus values
(Y of white = 1), each of R′, G′, B′ is clamped to [0, 1], then encoded with
R = 1.055·R′^(1/2.4) − 0.055. Two consequences, both kept as printed:

- no chromatic adaptation: the D50/10° white has linear (R′, G′, B′) = (1.191, 0.972, 0.710),
  so it is out of gamut, clipped, and encoded as (1.000, 0.988, 0.860), a warm white; every
  colour is shifted the same way;
- no linear segment near black: the true sRGB curve is 12.92·v for v ≤ 0.0031308. The printed
  curve maps 0 to −0.055 and is negative for R′ < (0.055/1.055)^2.4 ≈ 8.3·10⁻⁴. **We clamp the
  encoded result to [0, 1]** so that both modes return displayable values; this changes only
  those near-black channels, which any display shows as 0 anyway.

``managed`` is the colour-managed conversion: Bradford chromatic adaptation (von Kries form)
from the white of the illuminant/observer used for XYZ (D50/10° by default, computed by
:func:`~sandlight.colour.spectrum.white_point_xyz`, so the perfect reflector is exactly white) to
the sRGB white (D65, xy = 0.3127, 0.3290), the sRGB matrix derived from the IEC 61966-2-1
primaries and white (the 4-decimal printed matrix would leave white at R = 0.9998), clipping to
[0, 1], then the full
IEC 61966-2-1 encoding with its linear segment, all from colour-science. XYZ from the 10°
observer is used with the 2° sRGB definition, as the paper does; the adaptation makes white
white.

Out of gamut: a colour is flagged when a linear channel falls outside [0, 1] by more than
:data:`GAMUT_TOLERANCE` before clipping (``return_out_of_gamut=True``).

References
----------
- IEC 61966-2-1:1999, *Multimedia systems and equipment — Colour measurement and management —
  Part 2-1: Default RGB colour space — sRGB*.
- Lam, K. M. (1985), *Metamerism and colour constancy*, PhD thesis, University of Bradford
  (the Bradford transform).
- CIE 015:2018, *Colorimetry*, 4th edition, §8.2.1 (CIELAB).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

import colour
from sandlight.colour.spectrum import DEFAULT_ILLUMINANT, DEFAULT_OBSERVER, white_point_xyz
from sandlight.errors import ParameterError

__all__ = [
    "MODES",
    "GAMUT_TOLERANCE",
    "PAPER_XYZ_TO_LINEAR_RGB",
    "paper_encoding",
    "xyz_to_srgb",
    "xyz_to_lab",
    "srgb_to_uint8",
]

MODES = ("managed", "paper")

# Linear channels within this distance of [0, 1] count as in gamut: the perfect reflector lands
# on 1 only up to floating-point rounding of the chained matrices (~1e-15).
GAMUT_TOLERANCE = 1e-6

# Paper §4.1.1, the XYZ → (R', G', B') matrix exactly as printed.
PAPER_XYZ_TO_LINEAR_RGB: NDArray[np.float64] = np.array(
    [
        [3.2410, -1.5374, -0.4986],
        [-0.9692, 1.8760, 0.0416],
        [0.0556, -0.2040, 1.0570],
    ]
)
PAPER_XYZ_TO_LINEAR_RGB.setflags(write=False)

_SRGB = colour.RGB_COLOURSPACES["sRGB"]
_SRGB_WHITE_XYZ = colour.xy_to_XYZ(_SRGB.whitepoint)
# IEC 61966-2-1 defines sRGB by its primaries and D65 white; its printed matrices (which
# colour-science ships) are 4-decimal roundings that send white to (0.99984, 1.0001, 1.00007).
# The matrix derived from the primaries sends white to (1, 1, 1) to rounding error.
_XYZ_TO_LINEAR_SRGB = np.linalg.inv(colour.models.normalised_primary_matrix(_SRGB.primaries, _SRGB.whitepoint))


def _validated_xyz(xyz: ArrayLike) -> NDArray[np.float64]:
    try:
        arr = np.asarray(xyz, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("xyz", xyz, "an array of numbers of shape (..., 3)") from None
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ParameterError("xyz", f"array of shape {arr.shape}", "shape (..., 3)")
    if not np.all(np.isfinite(arr)):
        raise ParameterError("xyz", "an array containing NaN or inf", "finite values")
    return arr


def _validated_mode(mode: str) -> str:
    if mode not in MODES:
        raise ParameterError("mode", mode, f"one of {MODES}")
    return mode


def paper_encoding(linear: ArrayLike) -> NDArray[np.float64]:
    """The paper's gamma correction, exactly as printed (§4.1.1), without clamping.

    Parameters
    ----------
    linear
        Linear channel value R′ in [0, 1].

    Returns
    -------
    numpy.ndarray
        1.055·R′^γ − 0.055 with γ = 1/2.4; in [−0.055, 1].
    """
    v = np.asarray(linear, dtype=float)
    return 1.055 * v ** (1.0 / 2.4) - 0.055


def _linear_rgb(xyz: NDArray, mode: str, illuminant: str, observer: str) -> NDArray:
    if mode == "paper":
        # §4.1.1: (R', G', B')ᵀ = M · (X, Y, Z)ᵀ on the D50 values, no adaptation.
        return xyz @ PAPER_XYZ_TO_LINEAR_RGB.T
    source_white = white_point_xyz(illuminant, observer)
    with colour.utilities.domain_range_scale("reference"):
        adapted = colour.adaptation.chromatic_adaptation_VonKries(
            xyz, source_white, _SRGB_WHITE_XYZ, transform="Bradford"
        )
    return adapted @ _XYZ_TO_LINEAR_SRGB.T


def xyz_to_srgb(
    xyz: ArrayLike,
    mode: str = "managed",
    *,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
    return_out_of_gamut: bool = False,
) -> NDArray[np.float64] | tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Encoded sRGB of tristimulus values.

    Parameters
    ----------
    xyz
        CIE XYZ, shape (..., 3), on the [0, 1] scale (Y = 1 for the perfect reflector), as
        returned by :func:`~sandlight.colour.spectrum.spectrum_to_xyz`.
    mode
        ``"managed"``: Bradford adaptation to D65 and the full IEC 61966-2-1 encoding;
        ``"paper"``: §4.1.1 as printed (see the module docstring).
    illuminant, observer
        Illuminant and observer the XYZ were computed with; their white is the source white of
        the adaptation in managed mode. Paper mode ignores them, as the paper applied its matrix
        to D50 values without adaptation.
    return_out_of_gamut
        Also return a boolean array, shape (...), true where a linear channel was outside
        [0, 1] by more than :data:`GAMUT_TOLERANCE` and was clipped.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Encoded (non-linear) sRGB in [0, 1]; with ``return_out_of_gamut``, a tuple
        ``(rgb, out_of_gamut)``.

    Notes
    -----
    ======  ==============================  ===================
    Domain  Scale                           Range
    ======  ==============================  ===================
    XYZ     [0, 1], Y = 1 for white          encoded RGB [0, 1]
    ======  ==============================  ===================

    Examples
    --------
    >>> from sandlight.colour import white_point_xyz, xyz_to_srgb
    >>> xyz_to_srgb(white_point_xyz()).round(6)
    array([ 1.,  1.,  1.])
    >>> xyz_to_srgb(white_point_xyz(), mode="paper").round(3)
    array([ 1.   ,  0.988,  0.86 ])
    """
    arr = _validated_xyz(xyz)
    mode = _validated_mode(mode)
    linear = _linear_rgb(arr, mode, illuminant, observer)
    out_of_gamut = np.any((linear < -GAMUT_TOLERANCE) | (linear > 1.0 + GAMUT_TOLERANCE), axis=-1)
    linear = np.clip(linear, 0.0, 1.0)
    if mode == "paper":
        # Clamp of the *encoded* value: the printed curve is negative below R' ≈ 8.3e-4.
        rgb = np.clip(paper_encoding(linear), 0.0, 1.0)
    else:
        with colour.utilities.domain_range_scale("reference"):
            rgb = np.asarray(colour.models.eotf_inverse_sRGB(linear), dtype=float)
    if return_out_of_gamut:
        return rgb, out_of_gamut
    return rgb


def xyz_to_lab(
    xyz: ArrayLike, *, illuminant: str = DEFAULT_ILLUMINANT, observer: str = DEFAULT_OBSERVER
) -> NDArray[np.float64]:
    """CIELAB (CIE 1976 L*a*b*) relative to the perfect reflector under the same illuminant.

    Parameters
    ----------
    xyz
        CIE XYZ, shape (..., 3), on the [0, 1] scale.
    illuminant, observer
        Those the XYZ were computed with; the reference white X_n, Y_n, Z_n is their
        :func:`~sandlight.colour.spectrum.white_point_xyz` (D50/10° by default).

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        L* in [0, 100], a*, b* (unbounded, about ±128 for object colours).

    Notes
    -----
    =======  =======  ========================
    Domain   Scale    Range
    =======  =======  ========================
    XYZ      [0, 1]   L* [0, 100], a*, b*
    =======  =======  ========================

    Examples
    --------
    >>> from sandlight.colour import white_point_xyz, xyz_to_lab
    >>> xyz_to_lab(white_point_xyz()).round(6) + 0.0
    array([ 100.,    0.,    0.])
    """
    arr = _validated_xyz(xyz)
    white_xy = colour.XYZ_to_xy(white_point_xyz(illuminant, observer))
    with colour.utilities.domain_range_scale("reference"):
        return np.asarray(colour.XYZ_to_Lab(arr, illuminant=white_xy), dtype=float)


def srgb_to_uint8(rgb: ArrayLike) -> NDArray[np.uint8]:
    """8-bit code values of encoded sRGB.

    Parameters
    ----------
    rgb
        Encoded sRGB, any shape, nominally in [0, 1]; values outside are clipped.

    Returns
    -------
    numpy.ndarray of uint8
        round(255·clip(rgb, 0, 1)).
    """
    arr = np.asarray(rgb, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ParameterError("rgb", "an array containing NaN or inf", "finite values in [0, 1]")
    return np.rint(np.clip(arr, 0.0, 1.0) * 255.0).astype(np.uint8)
