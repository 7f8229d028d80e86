"""The validation report: ``docs/validation.md``, written (or updated) from the results.

Everything between ``<!-- BEGIN validation:… -->`` / ``<!-- END validation:… -->`` markers is
written here; hand-written text around the blocks is kept when the report is updated.

Public objects
--------------
REPORT_BLOCKS
    The names of the generated blocks.
write_report
    Writes the report (Markdown), atomically.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from sandlight.errors import ParameterError
from sandlight.validation.scoring import BandError, ValidationResult
from sandlight.validation.variants import DIAGNOSTIC_VARIANTS

if TYPE_CHECKING:
    from sandlight.engine import ReflectanceResult

__all__ = ["REPORT_BLOCKS", "write_report"]

REPORT_BLOCKS = ("command", "results", "figures", "variants", "figure3")
_BLOCK_RE = r"<!-- BEGIN validation:{name} -->\n.*?<!-- END validation:{name} -->"

_SKELETON = """# Validation against measured spectra

sandlight's reflectance against USGS laboratory spectra of samples whose presets were set from the
sample descriptions, never fitted to the spectra (issue 3 §3). Everything between `BEGIN`/`END`
markers is written by `sandlight validate`; text outside them is kept when the report is updated.

## How to reproduce

{command}

## Results

Targets: RMS ≤ 0.02 over 400–700 nm and ≤ 0.03 over 400–2500 nm.

{results}

## Spectra

{figures}

## Diagnostic variants

Each variant changes one thing in a preset, to see which physics can move the model by the size
of the miss. They are diagnostics, not fits.

{variants}

## The paper's Figure 3, from the model

{figure3}
"""


def _block(name: str, body: str) -> str:
    return f"<!-- BEGIN validation:{name} -->\n{body.rstrip()}\n<!-- END validation:{name} -->"


def _fmt_band(e: BandError) -> str:
    return f"{e.rms:.4f} ± {e.rms_mc:.4f}"


def _results_block(results: Sequence[ValidationResult]) -> str:
    lines = [
        "| sample | band | RMS error ± MC | target | verdict | max abs error ± MC (at λ) | mean bias | points |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        for e in r.errors.values():
            lines.append(
                f"| {r.sample.name} | {e.band} | {_fmt_band(e)} | ≤ {e.target_rms:g} | **{e.verdict}** | "
                f"{e.max_abs:.4f} ± {e.max_abs_mc:.4f} ({e.max_at_nm:g} nm) | {e.bias:+.4f} | {e.points} |"
            )
    lines.append("")
    lines.append(
        "Mean bias = mean(model − measured): positive means the model is too bright. ± MC is the Monte "
        "Carlo error bar (bound for correlated noise, see `sandlight.validation`)."
    )
    for r in results:
        lines.append(
            f"- **{r.sample.name}**: {_traced_text(r)} ({r.sample.description}); measured "
            f"spectrum `{r.sample.spectrum}`; {r.rays:,} rays per wavelength, seed {r.seed}, "
            f"{r.wavelengths_nm.size} wavelengths, {r.skipped} skipped (no usable measurement), "
            f"model run {r.elapsed_s:.1f} s."
        )
    return "\n".join(lines)


def _traced_text(r: ValidationResult) -> str:
    if r.sample.medium is None:
        return f"preset `{r.sample.preset}`"
    return f"{type(r.sample.medium).__name__} `{json.dumps(r.sample_values)}`"


def _figures_block(results: Sequence[ValidationResult], figure_paths: Sequence[Path], report_dir: Path) -> str:
    lines = []
    for r, p in zip(results, figure_paths):
        rel = os.path.relpath(p, report_dir)
        lines.append(f"![{r.sample.name}: model vs measurement]({rel})\n")
        lines.append(_values_table(r))
        lines.append("")
    return "\n".join(lines)


def _values_table(r: ValidationResult) -> str:
    keep = [lam for lam in (400, 450, 500, 550, 600, 650, 700, 1000, 1500, 2000, 2500) if lam in r.wavelengths_nm]
    idx = [int(np.flatnonzero(r.wavelengths_nm == lam)[0]) for lam in keep]
    head = "| λ (nm) | " + " | ".join(f"{lam:g}" for lam in keep) + " |"
    sep = "|---|" + "---|" * len(keep)
    model = "| model | " + " | ".join(f"{r.model[i]:.3f}" for i in idx) + " |"
    meas = "| measured | " + " | ".join(f"{r.measured[i]:.3f}" for i in idx) + " |"
    return "\n".join([head, sep, model, meas])


def _variants_block(variants: Sequence[ValidationResult] | None, reference: Sequence[ValidationResult]) -> str:
    if not variants:
        return "Not run in this report (`--no-variants`)."
    by_name = {r.sample.name: r for r in reference}
    lines = [
        f"Run at {variants[0].rays:,} rays per wavelength (seed {variants[0].seed}), same grid and scoring as "
        "above; the reference row is the preset.",
        "",
        "| sample | variant | probes | RMS 400–700 | RMS 400–2500 | bias 400–700 | bias 400–2500 | "
        "ρ 450 model / meas | ρ 650 | ρ 1500 |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]

    def row(r: ValidationResult, probes: str) -> str:
        vis, full = r.errors["400–700 nm"], r.errors["400–2500 nm"]
        at = []
        for lam in (450.0, 650.0, 1500.0):
            i = np.flatnonzero(r.wavelengths_nm == lam)
            at.append(f"{r.model[i[0]]:.3f} / {r.measured[i[0]]:.3f}" if i.size else "–")
        return (
            f"| {r.sample.name} | {r.label} | {probes} | {_fmt_band(vis)} | {_fmt_band(full)} | {vis.bias:+.3f} | "
            f"{full.bias:+.3f} | " + " | ".join(at) + " |"
        )

    seen = set()
    hypotheses = {v.label: v.hypothesis for v in DIAGNOSTIC_VARIANTS}
    for r in variants:
        if r.sample.name not in seen and r.sample.name in by_name:
            seen.add(r.sample.name)
            lines.append(row(by_name[r.sample.name], "reference"))
        lines.append(row(r, hypotheses.get(r.label, "")))
    return "\n".join(lines)


def _figure3_block(path: Path | None, report_dir: Path, spectra: dict | None) -> str:
    if path is None:
        return "Not run in this report."
    rel = os.path.relpath(path, report_dir)
    wl = spectra["wavelengths_nm"]
    keep = [lam for lam in (450, 550, 650, 900, 1500, 2200) if lam in wl]
    idx = [int(np.flatnonzero(wl == lam)[0]) for lam in keep]
    lines = [
        f"![Figure 3 from the model: quartz, iron oxide and the 98/2 mixture]({rel})",
        "",
        f"Model, {spectra['quartz'].rays:,} rays per wavelength. Dotted: pure quartz (the GDS76 preset's "
        "host); dashed: pure iron-oxide powder of 2.5 µm particles; solid: 98 wt% quartz + 2 wt% iron oxide as "
        "separate 2.5 µm particles. Grey: USGS measurements where the library has them.",
        "",
        "| spectrum | " + " | ".join(f"ρ {lam:g}" for lam in keep) + " |",
        "|---|" + "---|" * len(keep),
    ]

    def row(name: str, r: ReflectanceResult) -> str:
        return f"| {name} | " + " | ".join(f"{r.values[i]:.3f}" for i in idx) + " |"

    lines.append(row("pure quartz", spectra["quartz"]))
    for mineral in ("hematite", "goethite"):
        lines.append(row(f"pure {mineral}", spectra[mineral]["powder"]))
        lines.append(row(f"98/2 quartz + {mineral}", spectra[mineral]["mixture"]))
    return "\n".join(lines)


def write_report(
    path: str | os.PathLike,
    results: Sequence[ValidationResult],
    *,
    figure_paths: Sequence[str | os.PathLike],
    command: str,
    variants: Sequence[ValidationResult] | None = None,
    figure3_path: str | os.PathLike | None = None,
    figure3: dict | None = None,
) -> None:
    """Writes the validation report (Markdown), atomically.

    If ``path`` already holds a report with ``<!-- BEGIN validation:… -->`` /
    ``<!-- END validation:… -->`` blocks, only those blocks are replaced and any hand-written
    text around them (a discussion) is kept; otherwise a new report is written with the sections
    How to reproduce, Results, Spectra, Diagnostic variants and the paper's Figure 3.

    Parameters
    ----------
    path : str or os.PathLike
        The Markdown file.
    results : sequence of ValidationResult
        From :func:`sandlight.validation.samples.validate`.
    figure_paths : sequence of path
        The PNG of each result, in the same order (linked relative to the report).
    command : str
        The command that produced the report, shown verbatim.
    variants : sequence of ValidationResult, optional
        From :func:`sandlight.validation.variants.run_variants`.
    figure3_path : path, optional
        The PNG of :func:`sandlight.validation.figure3.plot_figure3`; ``figure3`` the spectra it shows.
    """
    from sandlight.io import atomic_path

    if len(figure_paths) != len(results):
        raise ParameterError("figure_paths", len(figure_paths), f"one path per result ({len(results)})")
    path = Path(path)
    report_dir = path.parent.resolve()
    fig_paths = [Path(p).resolve() for p in figure_paths]
    bodies = {
        "command": f"```\n{command}\n```",
        "results": _results_block(results),
        "figures": _figures_block(results, fig_paths, report_dir),
        "variants": _variants_block(variants, results),
        "figure3": _figure3_block(Path(figure3_path).resolve() if figure3_path else None, report_dir, figure3),
    }
    existing = path.read_text(encoding="utf-8") if path.is_file() else ""
    if existing and all(re.search(_BLOCK_RE.format(name=n), existing, re.S) for n in REPORT_BLOCKS):
        text = existing
        for name, body in bodies.items():
            text = re.sub(_BLOCK_RE.format(name=name), lambda _m, n=name, b=body: _block(n, b), text, flags=re.S)
    else:
        text = _SKELETON.format(**{n: _block(n, b) for n, b in bodies.items()})
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
