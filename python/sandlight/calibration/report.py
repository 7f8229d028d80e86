"""Reports of a calibration: identifiability, Markdown tables, figures and the derived k table.

Public objects
--------------
IDENTIFIABLE_SIGMA_LOG10_K
    Largest standard error of log10 k (decades) for which k counts as identified.
identifiability
    Per end-member and wavelength: ∂ρ/∂log10 k, the error of log10 k the measurement and Monte
    Carlo errors imply, whether that sample sees k, and the combined verdict per wavelength.
markdown_residuals, markdown_identifiability
    Markdown tables of a fit's residuals and of the identifiability.
plot_calibration
    Figure: fitted k with its identifiability, σ(log10 k) per end-member, measured vs model.
write_k_table, read_k_table
    The fitted k with the shipped n, in the format of ``sandlight/data/optical/*.csv``, with a
    header that says it is derived by calibration and how; and reading such a file back.

Identifiability. At wavelength λ, end-member s is consistent within two standard errors with
every x = log10 k for which |ρ_s(λ, x) − ρ_s(λ, x̂)| ≤ 2σ_si (x̂ the fitted value, σ_si the
measurement ⊕ Monte Carlo standard error); σ_s is a quarter of the width of that interval
around x̂, and the end-members together give σ from Σ_s [(ρ_s(x) − ρ_s(x̂))/σ_si]² ≤ 4. Where ρ
is linear in x this is σ_si / |∂ρ_s/∂x|, the sensitivity |∂ρ/∂log10 k| turned into an error of
log10 k. Unlike that local value it stays right at a plateau: the local derivative at a fitted
x just below an opaque plateau calls k determined where the data only bound it from below, and
in a round trip on synthetic data the true k then lay a decade above the fit at "identified"
wavelengths. k is *identifiable* at λ where the combined interval is bounded on both sides
within the k grid and σ ≤ :data:`IDENTIFIABLE_SIGMA_LOG10_K`. An end-member that does not see k
is *opaque* when its interval reaches the largest tabulated k (grains absorb all the light that
enters them; only their surface reflection is left), *transparent* when it reaches the smallest
(absorption along the paths too weak to show), else *flat* (bounded, but wider than the
threshold).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ModelFileError
from sandlight.io import atomic_path

if TYPE_CHECKING:
    import os

    from sandlight.calibration.fit import KFit
    from sandlight.calibration.tables import ReflectanceTable

__all__ = [
    "IDENTIFIABLE_SIGMA_LOG10_K",
    "Identifiability",
    "identifiability",
    "markdown_residuals",
    "markdown_identifiability",
    "plot_calibration",
    "write_k_table",
    "read_k_table",
]

#: A factor of 2 in k (0.3 decades).
IDENTIFIABLE_SIGMA_LOG10_K = math.log10(2.0)


@dataclass(frozen=True)
class Identifiability:
    """Result of :func:`identifiability` (arrays of shape (S, nλ) unless stated).

    Attributes
    ----------
    member_ids : tuple of str
    wavelengths_nm : numpy.ndarray, shape (nλ,)
    log10_k : numpy.ndarray, shape (nλ,)
        The k at which it is evaluated (the fit's).
    drho_dlog10_k : numpy.ndarray
    sigma_rho : numpy.ndarray
        Measurement ⊕ Monte Carlo standard error of ρ.
    sigma_log10_k : numpy.ndarray
        σ_s, a quarter of the width of the 2σ interval of log10 k, per end-member (decades).
    state : numpy.ndarray of str
        ``"sees k"``, ``"opaque"``, ``"transparent"``, ``"flat"`` or ``"not measured"``.
    combined_sigma_log10_k : numpy.ndarray, shape (nλ,)
        σ of all end-members together (inf where the interval reaches an end of the k grid).
    interval_log10_k : numpy.ndarray, shape (2, nλ)
        The two-standard-error interval of log10 k of all end-members together (Δχ² ≤ 4
        around the fitted value), lower and upper end; an end at the grid's limit means unbounded.
    identifiable : numpy.ndarray of bool, shape (nλ,)
    """

    member_ids: tuple
    wavelengths_nm: np.ndarray
    log10_k: np.ndarray
    drho_dlog10_k: np.ndarray
    sigma_rho: np.ndarray
    sigma_log10_k: np.ndarray
    state: np.ndarray
    combined_sigma_log10_k: np.ndarray
    interval_log10_k: np.ndarray
    identifiable: np.ndarray

    def verdict(self, i: int) -> str:
        """One line for wavelength index i: which end-members see k, or why none does."""
        states = self.state[:, i]
        seeing = [m for m, s in zip(self.member_ids, states) if s == "sees k"]
        if self.identifiable[i]:
            return f"identified by {len(seeing)} of {len(states)}" if seeing else "identified jointly"
        counts = Counter(s for s in states if s != "sees k")
        return "not identifiable: " + ", ".join(f"{n} {s}" for s, n in counts.most_common())


#: Δχ² of the interval that defines σ: 4, the two-standard-error interval, whose half-width is 2σ
#: where ρ is linear in log10 k.
_DCHI2 = 4.0


def _interval(dchi2: np.ndarray, x: np.ndarray, low: float, high: float):
    """Per column of ``x`` (rows: trial log10 k increasing, the fitted value at the middle row),
    the contiguous run of rows around the middle where dchi2 ≤ _DCHI2.

    Returns the run's ends in log10 k, each placed where √dchi2 crosses √_DCHI2 by linear
    interpolation between the last row inside and the first outside (exact where ρ is linear in
    log10 k, so σ is not rounded to the row spacing), and whether the run reaches the grid's
    top (``x ≥ high``) and bottom (``x ≤ low``): k is then bounded on one side only.
    """
    n = dchi2.shape[0]
    j = n // 2
    fail = dchi2 > _DCHI2
    rows = np.arange(n)[:, None]
    lo = np.where(fail & (rows < j), rows, -1).max(axis=0) + 1
    hi = np.where(fail & (rows > j), rows, n).min(axis=0) - 1
    columns = np.arange(dchi2.shape[1])
    root = np.sqrt(dchi2)
    limit = math.sqrt(_DCHI2)

    def crossing(inside: np.ndarray, outside: np.ndarray) -> np.ndarray:
        valid = (outside >= 0) & (outside < n)
        o = np.clip(outside, 0, n - 1)
        r_in, r_out = root[inside, columns], root[o, columns]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(valid & (r_out > r_in), (limit - r_in) / (r_out - r_in), 0.0)
        x_in, x_out = x[inside, columns], x[o, columns]
        return x_in + np.clip(t, 0.0, 1.0) * (x_out - x_in)

    return crossing(lo, lo - 1), crossing(hi, hi + 1), x[hi, columns] >= high, x[lo, columns] <= low


def identifiability(
    tables: Sequence[ReflectanceTable],
    log10_k: ArrayLike,
    sigma_measured: ArrayLike,
    *,
    threshold: float = IDENTIFIABLE_SIGMA_LOG10_K,
    points: int = 201,
) -> Identifiability:
    """Which end-members constrain k where (see the module docstring).

    Parameters
    ----------
    tables : sequence of ReflectanceTable
        On one wavelength grid.
    log10_k : array_like, shape (nλ,)
        Where to evaluate (normally ``KFit.log10_k_``).
    sigma_measured : array_like, broadcastable to (S, nλ)
        Measurement standard errors (NaN where not measured: that sample then does not count).
    threshold : float
        Largest σ(log10 k) that counts as identified (decades, > 0).
    points : int
        Trial values of log10 k on each side of the fitted one (geometrically spaced offsets
        from 10⁻⁴ decades to the whole k range) on which the intervals are found.

    Returns
    -------
    Identifiability
    """
    wl = tables[0].wavelengths_nm
    shape = (len(tables), wl.size)
    low = max(t.log10_k[0] for t in tables)
    high = min(t.log10_k[-1] for t in tables)
    x = np.clip(np.asarray(log10_k, dtype=float), low, high)
    steps = np.geomspace(1e-4, high - low, points)
    trial = np.clip(x[None, :] + np.concatenate([-steps[::-1], [0.0], steps])[:, None], low, high)
    s_meas = np.broadcast_to(np.asarray(sigma_measured, dtype=float), shape)
    drho = np.empty(shape)
    sigma_rho = np.empty(shape)
    sigma_x = np.empty(shape)
    state = np.empty(shape, dtype=object)
    total = np.zeros(trial.shape)
    for s, t in enumerate(tables):
        rho, drho[s] = t(x)
        sigma_rho[s] = np.sqrt(s_meas[s] ** 2 + t.stderr_at(x) ** 2)
        counted = np.isfinite(sigma_rho[s])
        at_trial = np.array([t(row)[0] for row in trial])
        d2 = np.where(counted, ((at_trial - rho) / np.where(counted, sigma_rho[s], 1.0)) ** 2, 0.0)
        total += d2
        lo, hi, top, bottom = _interval(np.where(counted, d2, np.inf), trial, low, high)
        sigma_x[s] = np.where(counted, 0.25 * (hi - lo), np.inf)
        near_opaque = np.abs(rho - t.rho[:, -1]) <= 2 * sigma_rho[s]
        state[s] = np.select(
            [~counted, top & bottom, top, bottom, sigma_x[s] <= threshold],
            ["not measured", np.where(near_opaque, "opaque", "transparent"), "opaque", "transparent", "sees k"],
            "flat",
        )
    lo, hi, top, bottom = _interval(total, trial, low, high)
    combined = 0.25 * (hi - lo)
    bounded = ~top & ~bottom
    return Identifiability(
        tuple(t.member_id for t in tables),
        wl,
        x,
        drho,
        sigma_rho,
        sigma_x,
        state.astype(str),
        np.where(bounded, combined, np.inf),
        np.array([lo, hi]),
        bounded & (combined <= threshold),
    )


def _at(wl: np.ndarray, report_nm: Iterable[float]) -> list[int]:
    """Indices of the grid wavelengths nearest to each of ``report_nm`` (duplicates dropped)."""
    out = []
    for lam in report_nm:
        i = int(np.argmin(np.abs(wl - lam)))
        if i not in out:
            out.append(i)
    return out


def markdown_residuals(
    fit: KFit,
    *,
    bands_nm: Sequence[tuple[float, float]] = ((400.0, 700.0), (350.0, 2500.0)),
    held_out: Mapping[str, tuple[ArrayLike, ArrayLike]] | None = None,
) -> str:
    """Markdown table: RMS and mean bias (model − measured) per end-member and band.

    ``held_out``: optional dict id → (predicted, measured) arrays on the fit's grid, reported
    as predictions below the fitted rows.
    """
    wl = fit.wavelengths_nm_
    head = "| end-member | role | " + " | ".join(f"RMS {a:g}–{b:g} nm | bias {a:g}–{b:g}" for a, b in bands_nm) + " |"
    lines = [head, "|---|---|" + "---|---|" * len(bands_nm)]

    def row(name: str, role: str, residual: np.ndarray) -> str:
        cells = []
        for a, b in bands_nm:
            band = (wl >= a) & (wl <= b) & np.isfinite(residual)
            r = residual[band]
            cells += [f"{math.sqrt(np.mean(r**2)):.4f}", f"{np.mean(r):+.4f}"] if r.size else ["–", "–"]
        return f"| {name} | {role} | " + " | ".join(cells) + " |"

    for i, name in enumerate(fit.member_ids_):
        lines.append(row(name, "fitted", fit.residuals_[i]))
    for name, (predicted, measured) in (held_out or {}).items():
        lines.append(row(name, "**predicted**", np.asarray(predicted) - np.asarray(measured)))
    return "\n".join(lines)


def markdown_identifiability(
    ident: Identifiability, fit: KFit, report_nm: Iterable[float], *, with_model: Identifiability | None = None
) -> str:
    """Markdown table at chosen wavelengths: fitted k ± σ, σ(log10 k) per end-member, verdict.

    ``with_model``: the identifiability with the fit's model error added to the measurement
    error, shown as two more columns (its combined σ and verdict).
    """
    wl = ident.wavelengths_nm

    def fmt_sigma(x: float) -> str:
        return f"{x:.2f}" if x < 10 else "≫1"

    extra = " | σ log10 k (data + model) | verdict with model error" if with_model is not None else ""
    head = (
        "| λ (nm) | k fitted | σ log10 k (fit) | σ log10 k (data) | "
        + " | ".join(f"σ {m}" for m in ident.member_ids)
        + " | verdict"
        + extra
        + " |"
    )
    lines = [head, "|---|---|---|---|" + "---|" * len(ident.member_ids) + "---|" * (3 if with_model is not None else 1)]
    for i in _at(wl, report_nm):
        cells = [
            fmt_sigma(ident.sigma_log10_k[s, i])
            + ("" if ident.state[s, i] == "sees k" else f" ({ident.state[s, i][0]})")
            for s in range(len(ident.member_ids))
        ]
        row = (
            f"| {wl[i]:g} | {fit.k_[i]:.3g} | {fit.sigma_log10_k_[i]:.2f} | "
            + f"{fmt_sigma(ident.combined_sigma_log10_k[i])} | "
            + " | ".join(cells)
            + f" | {ident.verdict(i)}"
        )
        if with_model is not None:
            row += f" | {fmt_sigma(with_model.combined_sigma_log10_k[i])} | {with_model.verdict(i)}"
        lines.append(row + " |")
    return "\n".join(lines)


def plot_calibration(
    path: str | os.PathLike[str],
    fit: KFit,
    measured: np.ndarray,
    ident: Identifiability,
    *,
    mineral: str,
    errors: str,
    reference: tuple[ArrayLike, ArrayLike] | None = None,
    reference_label: str = "shipped table",
    truth: tuple[ArrayLike, ArrayLike] | None = None,
) -> None:
    """Three panels: k(λ) fitted (band: ±σ of the fit; grey: not identifiable) against a
    reference k (``reference``: (wavelengths, k), named ``reference_label``, e.g. the
    literature prior) and a known ``truth`` (same form, synthetic runs); σ(log10 k) per
    end-member with the threshold; measured (lines) vs model (dots). ``errors`` names the
    errors ``ident`` was computed with (the σ panel's label)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    wl = fit.wavelengths_nm_
    fig, (a, b, c) = plt.subplots(3, 1, figsize=(8.0, 10.0), dpi=110, sharex=True)
    for lo, hi in _runs(wl, ~ident.identifiable):
        for ax in (a, b, c):
            ax.axvspan(lo, hi, color="0.88", lw=0)
    a.semilogy(wl, fit.k_, "C3-", lw=1.5, label=f"{mineral} k, fitted")
    # The band is the fit's ±σ, clipped to the tabulated k range (where σ is huge, the prior is all).
    low, high = fit.k_range_log10_
    band = [10 ** np.clip(fit.log10_k_ + sign * fit.sigma_log10_k_, low, high) for sign in (-1, 1)]
    a.fill_between(wl, band[0], band[1], color="C3", alpha=0.25, lw=0)
    if reference is not None:
        a.semilogy(reference[0], reference[1], "k--", lw=1, label=reference_label)
    if truth is not None:
        a.semilogy(truth[0], truth[1], "C0:", lw=2, label="true k (synthetic)")
    a.set_ylabel("k")
    a.grid(alpha=0.3, which="both")
    a.legend(fontsize=8)
    a.set_title(
        f"{mineral}: calibrated k (grey: not identifiable, σ log10 k > {IDENTIFIABLE_SIGMA_LOG10_K:.2f})", fontsize=9
    )
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(fit.member_ids_)))
    for s, (name, colour) in enumerate(zip(fit.member_ids_, colours)):
        b.semilogy(wl, np.clip(ident.sigma_log10_k[s], 1e-3, 1e3), "-", color=colour, lw=1, label=name)
        c.plot(wl, measured[s], "-", color=colour, lw=1, label=name)
        c.plot(wl, fit.fitted_[s], "o", color=colour, ms=2.5)
    b.semilogy(wl, np.clip(ident.combined_sigma_log10_k, 1e-3, 1e3), "k-", lw=1.5, label="combined")
    b.axhline(IDENTIFIABLE_SIGMA_LOG10_K, color="C3", ls="--", lw=1)
    b.set_ylabel(f"σ log10 k from the {errors}", fontsize=8)
    b.set_ylim(1e-3, 1e3)
    b.grid(alpha=0.3, which="both")
    b.legend(fontsize=7, ncol=4)
    c.set_ylabel("reflectance")
    c.set_xlabel("wavelength (nm)")
    c.set_title("measured (lines) vs model at the fitted k (dots)", fontsize=9)
    c.grid(alpha=0.3)
    c.legend(fontsize=7, ncol=4)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)


def _runs(wl: np.ndarray, flag: np.ndarray) -> list[tuple[float, float]]:
    """Wavelength intervals (half-way to the neighbours) where ``flag`` is True."""
    edges = np.concatenate([[wl[0]], 0.5 * (wl[1:] + wl[:-1]), [wl[-1]]])
    runs, start = [], None
    for i, f in enumerate(flag):
        if f and start is None:
            start = edges[i]
        if not f and start is not None:
            runs.append((start, edges[i]))
            start = None
    if start is not None:
        runs.append((start, edges[-1]))
    return runs


def write_k_table(
    path: str | os.PathLike[str], mineral: str, fit: KFit, ident: Identifiability, *, command: str, inputs: str
) -> None:
    """Writes the fitted k (with the shipped n) as ``wavelength_nm,n,k`` with a ``#`` header.

    The header follows ``sandlight/data/optical/*.csv`` (material, status, source, origin,
    licence, units, sampling, method) and says that the values are derived by calibration, with
    the command, the inputs, the RMS residuals and where k is not identifiable.
    """
    from sandlight.optics import complex_index

    wl = fit.wavelengths_nm_
    n = np.real(complex_index(mineral, wl))
    blind = ", ".join(f"{lo:.0f}-{hi:.0f}" for lo, hi in _runs(wl, ~ident.identifiable)) or "none"
    rms = ", ".join(f"{m} {r:.4f}" for m, r in fit.rms_.items())
    header = [
        f"material: {mineral}",
        "status: derived by calibration (the effective k of the engine's powders; docs/optical-constants.md)",
        "source: USGS Spectral Library Version 7 (Kokaly et al. 2017, doi:10.3133/ds1035), end-member spectra",
        f"origin: {inputs}",
        "licence: MIT (values computed by sandlight); input spectra public domain",
        "units: wavelength in nm (vacuum); n and k dimensionless",
        f"sampling: the calibration grid, {wl.size} wavelengths {wl[0]:g}-{wl[-1]:g} nm",
        f"method: {command}; n from the shipped table; RMS residuals {rms}; not identifiable (nm): {blind}",
    ]
    lines = [f"# {h}" for h in header] + ["wavelength_nm,n,k"]
    lines += [f"{lam:g},{nn:.6g},{kk:.6g}" for lam, nn, kk in zip(wl, n, fit.k_)]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")


def read_k_table(path: str | os.PathLike[str]) -> tuple[dict[str, str], np.ndarray, np.ndarray, np.ndarray]:
    """Reads a table of :func:`write_k_table`: ``(header, wavelength_nm, n, k)``.

    ``header`` maps each ``# key: value`` line's key to its value. A file that is not such a
    table (no ``derived by calibration`` status, wavelengths not increasing, k not finite and
    > 0) raises :class:`sandlight.errors.ModelFileError` naming it.
    """
    header, rows = {}, []
    try:
        for line in Path(path).read_text(encoding="utf-8").splitlines():
            if line.startswith("# "):
                key, _, value = line[2:].partition(": ")
                header[key] = value
            elif line and line != "wavelength_nm,n,k":
                rows.append([float(x) for x in line.split(",")])
        data = np.array(rows, dtype=float)
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise ModelFileError(f"{path}: not a calibrated k table ({exc})") from None
    ok = (
        header.get("status", "").startswith("derived by calibration")
        and data.ndim == 2
        and data.shape[0] >= 2
        and data.shape[1] == 3
        and bool(np.all(np.diff(data[:, 0]) > 0))
        and bool(np.all(np.isfinite(data[:, 2]) & (data[:, 2] > 0)))
    )
    if not ok:
        raise ModelFileError(f"{path}: not a calibrated k table (status, 'wavelength_nm,n,k' rows, k > 0)")
    return header, data[:, 0], data[:, 1], data[:, 2]
