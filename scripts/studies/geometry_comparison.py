#!/usr/bin/env python3
"""Explicit geometry against the on-the-fly engine (issue 9): reflectance tables and BRDFs.

Cases (normal incidence, directional-hemispherical reflectance, dry):

* monodisperse spheres, d = 0.25 mm, porosity 0.40, n = 1.544, absorption α in the grains,
  α = 0.5, 5 and 50 cm⁻¹ (issue 9's table);
* the same with polydisperse spheres (log-normal by mass, median 0.25 mm, σ_g = 1.4);
* the same with monodisperse prolate spheroids of aspect ratio 1.4;
* the ``red-dune`` preset at 450, 550 and 650 nm (its clay and silt stay on the fly in the
  pores of the packed sand, docs/geometry.md).

For every case it traces the explicit reference (one packing per sand, seed 1) and the
on-the-fly engine with ``memory`` = none, channel, cut and packed, and writes Markdown tables with
standard errors between the markers ``<!-- geometry-comparison:begin/end -->`` of
``docs/geometry.md`` (atomically). With ``--brdf`` it also measures principal-plane BRDFs at
0°, 30° and 60° incidence for the dark monodisperse spheres (α = 50 cm⁻¹) and writes
``docs/img/geometry-brdf.png`` and a table. With ``--diagnostics`` it writes two diagnostics
between ``<!-- geometry-diagnostics:begin/end -->``: escape by scattering order for the spheres
at α = 5 cm⁻¹, and grains with fines that scatter light many times inside each pore. With
``--settled`` it compares the two surfaces of the explicit reference for the monodisperse
spheres — the cut and the gravity-settled layer (default 2 reference-grain layers) — with the
on-the-fly engine (memory none and cut), and describes the settled packings (spheres and
spheroids ε = 1.4), between the markers ``<!-- geometry-settled:begin/end -->``. With
``--presets`` it compares every preset, dried (saturation 0), at 450, 550, 650 and 850 nm, between
``<!-- geometry-presets:begin/end -->``.

Usage::

    python scripts/studies/geometry_comparison.py [--scale 1.0] [--brdf] [--diagnostics] [--settled] [--presets]
                                          [--no-tables] [--threads 2]

``--scale`` multiplies every ray count (0.1 for a quick look).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from sandlight import _native
from sandlight.machine import describe
from sandlight.physics.composition import compose
from sandlight.physics.medium import native_medium
from sandlight.physics.packing import generate_packing, grain_medium, grains_with_fines, reference_grain_mm
from sandlight.physics.sizes import SizeDistribution
from sandlight.sample import SandSample

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "geometry.md"
BEGIN, END = "<!-- geometry-comparison:begin -->", "<!-- geometry-comparison:end -->"
BRDF_BEGIN, BRDF_END = "<!-- geometry-brdf:begin -->", "<!-- geometry-brdf:end -->"
DIAG_BEGIN, DIAG_END = "<!-- geometry-diagnostics:begin -->", "<!-- geometry-diagnostics:end -->"
SETTLED_BEGIN, SETTLED_END = "<!-- geometry-settled:begin -->", "<!-- geometry-settled:end -->"
PRESETS_BEGIN, PRESETS_END = "<!-- geometry-presets:begin -->", "<!-- geometry-presets:end -->"
PRESET_WAVELENGTHS_NM = (450.0, 550.0, 650.0, 850.0)
MEMORIES = ("none", "channel", "cut", "packed")
ALPHAS_PER_CM = (0.5, 5.0, 50.0)
#: Rays per α (or per preset wavelength) at --scale 1: about 0.3 % relative error or better.
RAYS = {0.5: 400_000, 5.0: 1_000_000, 50.0: 3_000_000, "preset": 600_000}
MAX_EVENTS, MAX_INTERNAL = 10_000_000, 10_000


def dhr(medium, rays, threads, seed=1):
    """(ρ, standard error, counts) at normal incidence."""
    c = medium.dhr(0.0, seed, 0, 0, rays, MAX_EVENTS, MAX_INTERNAL, threads)
    rho = c[1] / c[0]
    return rho, math.sqrt(rho * (1 - rho) / c[0]), c


def within_target(value, ref):
    """Issue 9's target: within 3 % relative or 0.002 absolute, whichever is larger."""
    return abs(value - ref) <= max(0.03 * ref, 0.002)


def packing_report(pk, d_mm=None, porosity=None, medium=None, threads=None, rays=0):
    """Packing figures: size, fractions, overlaps, chords, and light reaching the bottom."""
    empty, multiple = pk.point_statistics(200_000, 9)
    row = {
        "n": pk.n_particles,
        "period": pk.period_mm,
        "eta": pk.packing_fraction,
        "phi_sample": pk.sample_porosity,
        "phi_points": empty,
        "overlap_volume": multiple,
        "max_overlap": pk.max_overlap,
    }
    if d_mm is not None:
        ch = pk.pore_chords(4000, 10, 3)
        row["chord_ratio"] = ch.mean() / (2.0 / 3.0 * d_mm * porosity / (1 - porosity))
        row["chord_cv"] = ch.std() / ch.mean()
    if medium is not None and rays:
        # A copy of the sample cut off one period (H) below the top: what gets that deep.
        _, _, c = dhr(medium.explicit(pk, pk.period_mm[2]), rays, threads)
        row["bottom"] = c[3] / c[0]
    return row


def sphere_model(label, packing, depth_mm=math.inf, **optics):
    """Issue 9's monodisperse spheres (d = 0.25 mm, φ = 0.40) traced through ``packing``
    (label 'explicit') or on the fly with memory ``label``; ``optics``: grain_medium's."""
    if label == "explicit":
        return grain_medium([0.25], **optics).explicit(packing, depth_mm)
    return grain_medium([0.25], memory=label, depth_mm=depth_mm, **optics)


def run_case(name, make_medium, packing, rays, threads, label):
    """One line of a table: explicit and on-the-fly values."""
    out = {"case": name, "label": label}
    t0 = time.perf_counter()
    out["explicit"] = dhr(make_medium("none").explicit(packing), rays, threads)[:2]
    out["t_explicit"] = time.perf_counter() - t0
    for mem in MEMORIES:
        t0 = time.perf_counter()
        out[mem] = dhr(make_medium(mem), rays, threads)[:2]
        out[f"t_{mem}"] = time.perf_counter() - t0
    out["rays"] = rays
    print(
        f"{name:28s} {label:>10s}  explicit {out['explicit'][0]:.4f}  "
        + "  ".join(f"{m} {out[m][0]:.4f}" for m in MEMORIES),
        flush=True,
    )
    return out


def fmt(v, se):
    digits = 4 if v >= 0.01 else 5
    return f"{v:.{digits}f} ± {se:.{digits}f}"


def table(rows):
    head = (
        "| case | explicit | on-the-fly (none) | Δ | " + " | ".join(f"{m} | Δ" for m in MEMORIES[1:]) + " |\n"
        "|---|---|" + "---|---|" * len(MEMORIES) + "\n"
    )
    lines = []
    for r in rows:
        ref = r["explicit"][0]
        cells = [r["label"], fmt(*r["explicit"])]
        for m in MEMORIES:
            v = r[m][0]
            mark = "" if within_target(v, ref) else " ✗"
            cells += [fmt(*r[m]), f"{100 * (v / ref - 1):+.1f} %{mark}"]
        lines.append("| " + " | ".join(cells) + " |")
    return head + "\n".join(lines) + "\n"


def packing_table(reports):
    head = (
        "| sand | grains | box (mm) | η packed | φ (points) | overlap volume | max overlap / d | "
        "mean chord / (2/3)dφ/(1−φ) | chord sd/mean | rays deeper than H |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n"
    )
    lines = []
    for name, r in reports.items():
        box = "{:.2f} × {:.2f} × {:.2f}".format(*r["period"])
        chord = f"{r['chord_ratio']:.4f}" if "chord_ratio" in r else "–"
        cv = f"{r['chord_cv']:.3f}" if "chord_cv" in r else "–"
        bottom = f"{r['bottom']:.2e}" if "bottom" in r else "–"
        lines.append(
            f"| {name} | {r['n']} | {box} | {r['eta']:.4f} | {r['phi_points']:.4f} | {r['overlap_volume']:.2e} | "
            f"{r['max_overlap']:.1e} | {chord} | {cv} | {bottom} |"
        )
    return head + "\n".join(lines) + "\n"


def replace_block(text, begin, end, body):
    if begin in text and end in text:
        i, j = text.index(begin) + len(begin), text.index(end)
        return text[:i] + "\n" + body + text[j:]
    return text.rstrip() + f"\n\n{begin}\n{body}{end}\n"


def write_atomic(path: Path, text: str):
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def brdf_principal_plane(medium, theta_deg, rays, threads, stacks=18, slices=36):
    """Principal-plane BRDF (sr⁻¹) from fixed-incidence counts: signed view zenith (positive
    toward the light, i.e. backscatter side) and values with standard errors."""
    counts, _, launched, _ = medium.fixed_counts(
        stacks, slices, theta_deg, 0.0, 1, 0, 0, rays, MAX_EVENTS, MAX_INTERNAL, threads
    )
    geo = _native.hemisphere_geometry(stacks, slices)
    proj = geo["projected_solid_angles"]
    f = counts / (launched * proj)
    se = np.sqrt(counts) / (launched * proj)
    b = geo["bounds"]
    zen = np.degrees(np.arccos(np.clip(geo["centroids"][:, 2], -1, 1)))
    back = (b[:, 2] <= 1e-9) | ((b[:, 2] <= 0.0) & (b[:, 3] > 0.0))
    fwd = (b[:, 2] <= math.pi) & (b[:, 3] > math.pi)
    sel_b, sel_f = np.where(back)[0], np.where(fwd & ~back)[0]
    x = np.concatenate([-zen[sel_f], zen[sel_b]])
    order = np.argsort(x)
    idx = np.concatenate([sel_f, sel_b])[order]
    return x[order], f[idx], se[idx]


def run_brdf(scale, threads, packing):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rays = int(4_000_000 * scale)
    alpha = 5.0  # 50 cm⁻¹
    models = {
        (label if label == "explicit" else f"on-the-fly, memory {label}"): sphere_model(
            label, packing, alpha_per_mm=alpha
        )
        for label in ("explicit", "none", "cut", "packed")
    }
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), sharey=True)
    rows = []
    for ax, theta in zip(axes, (0.0, 30.0, 60.0)):
        curves = {}
        for name, m in models.items():
            x, f, se = brdf_principal_plane(m, theta, rays, threads)
            curves[name] = (x, f, se)
            ax.errorbar(x, f, yerr=2 * se, label=name, capsize=2, lw=1)
        ax.set_title(f"incidence {theta:.0f}°")
        ax.set_xlabel("view zenith (°), + toward the light")
        ax.axvline(theta, color="grey", lw=0.5, ls=":")
        # Backscatter peak: the patch nearest the light's direction over the mean of the two
        # patches 15°–25° beyond it on the same side (or on both sides for normal incidence).
        for name, (x, f, se) in curves.items():
            k = int(np.argmin(np.abs(x - theta)))
            side = np.abs(x - theta)
            ring = (side > 14) & (side < 26) & (np.sign(x) == (np.sign(x[k]) if theta > 0 else np.sign(x)))
            rows.append((theta, name, f[k], se[k], f[k] / f[ring].mean()))
    axes[0].set_ylabel("BRDF (sr⁻¹)")
    axes[0].legend(fontsize=8)
    fig.suptitle("Principal-plane BRDF, monodisperse spheres d = 0.25 mm, φ = 0.40, n = 1.544, α = 50 cm⁻¹")
    fig.tight_layout()
    out = ROOT / "docs" / "img" / "geometry-brdf.png"
    fd, tmp = tempfile.mkstemp(dir=out.parent, suffix=".png")
    os.close(fd)
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    body = (
        f"Rays per curve: {rays:,}; collector 18 × 36 patches (5° × 10°). Peak ratio: BRDF in the patch "
        "of the light's own direction over the mean 15°–25° away from it.\n\n"
        "| incidence | model | BRDF toward the light (sr⁻¹) | peak ratio |\n|---|---|---|---|\n"
    )
    body += "\n".join(f"| {t:.0f}° | {n} | {v:.4f} ± {s:.4f} | {r:.3f} |" for t, n, v, s, r in rows) + "\n\n"
    body += "![principal-plane BRDFs](img/geometry-brdf.png)\n"
    for r in rows:
        print(f"BRDF θi={r[0]:.0f} {r[1]:28s} f={r[2]:.4f}±{r[3]:.4f} peak ratio {r[4]:.3f}")
    return body


def run_diagnostics(scale, threads):
    """Diagnostics of what the memories capture (docs/geometry.md): escape by scattering order
    for monodisperse spheres at α = 5 cm⁻¹, grains with fines, where the next grain is met
    after a flight in the packing, transmission of non-absorbing slabs, and wet sand."""
    d = 0.25
    orders = (1, 2, 3, 4, 6, 10, MAX_EVENTS)
    pk = pk_spheres = generate_packing(grain_medium([d]), reference_mm=d, seed=1)
    rays = int(300_000 * scale)
    lines = [
        f"Escape by scattering order, monodisperse spheres, α = 5 cm⁻¹ ({rays:,} rays per run): the "
        "fraction of rays that escape after at most k events (runs capped at k events).\n",
        "| model | k = 1 | 2 | 3 | 4 | 6 | 10 | all |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label in ("explicit", "none", "cut", "packed"):
        m = sphere_model(label, pk, alpha_per_mm=0.5)
        cum = []
        for k in orders:
            c = m.dhr(0.0, 1, 0, 0, rays, k, MAX_INTERNAL, threads)
            cum.append(c[1] / c[0])
        lines.append(f"| {label} | " + " | ".join(f"{v:.4f}" for v in cum) + " |")
        print(f"orders {label}: " + " ".join(f"{v:.4f}" for v in cum), flush=True)
    rays = int(100_000 * scale)
    pk = generate_packing(grains_with_fines(), reference_mm=d, seed=1)
    lines += [
        "",
        f"Grains (d = 0.25 mm, φ = 0.40) with 2 µm fines making 90 % of the encounters "
        f"({rays:,} rays per run, one packing of seed 1); α in mm⁻¹ (1 mm⁻¹ = 10 cm⁻¹). "
        "Δ relative to explicit.\n",
        "| grains | α grains | α fines | explicit | " + " | ".join(f"{m} | Δ" for m in MEMORIES) + " |",
        "|---|---|---|---|" + "---|---|" * len(MEMORIES),
    ]
    for n_sand, a_sand, a_fines in ((1.0001, 0.0, 5.0), (1.544, 0.0, 5.0), (1.544, 0.5, 5.0), (1.544, 0.5, 0.0)):
        fines = dict(n=n_sand, alpha_per_mm=a_sand, fines_alpha_per_mm=a_fines)
        ref = dhr(grains_with_fines(**fines).explicit(pk), rays, threads)
        cells = [
            ("index-matched (n = 1.0001)" if n_sand < 1.01 else f"n = {n_sand:g}"),
            f"{a_sand:g}",
            f"{a_fines:g}",
            fmt(*ref[:2]),
        ]
        for mem in MEMORIES:
            v = dhr(grains_with_fines(**fines, memory=mem), rays, threads)
            mark = "" if within_target(v[0], ref[0]) else " ✗"
            cells += [fmt(*v[:2]), f"{100 * (v[0] / ref[0] - 1):+.1f} %{mark}"]
        lines.append("| " + " | ".join(cells) + " |")
        print("fines " + " | ".join(cells), flush=True)
    samples = int(30_000 * scale)
    lines += [
        "",
        f"Where the next grain is met after leaving one, monodisperse spheres ({samples:,} flights from "
        "uniform points on random grains of the packing, Lambertian directions): mean cosine of the "
        "incidence angle on the next grain, by flight length s. The on-the-fly (Boolean) model has "
        "2/3 at every length; equilibrium requires 2/3 on average.\n",
        "| s (mm) | flights | packing ⟨μ⟩ |",
        "|---|---|---|",
    ]
    for (lo, hi), count, mean in incidence_by_flight(pk_spheres, samples):
        lines.append(f"| {lo:g}–{hi:g} | {count} | {mean:.3f} |")
    lines += slab_rows(pk_spheres, scale, threads)
    lines += wet_sand_rows(scale, threads)
    return (
        f"Generated by `scripts/studies/geometry_comparison.py --diagnostics --scale {scale:g}`.\n\n"
        + "\n".join(lines)
        + "\n"
    )


def slab_rows(pk, scale, threads, depths_mm=(1.0, 3.0)):
    """Transmission of non-absorbing slabs of monodisperse spheres: how far light diffuses in the
    packing and on the fly, free of absorption and of the surface's single scattering."""
    rays = int(400_000 * scale)
    lines = [
        "",
        f"Non-absorbing slabs of monodisperse spheres (α = 0), normal incidence, {rays:,} rays per run: "
        "transmittance T (rays deeper than the slab) and events per ray. Thickness from the cut "
        "plane (explicit and `cut`) or from the boundary plane (`none`). Δ relative to explicit.\n",
        "| thickness | explicit | none | Δ | cut | Δ | packed | Δ | events per ray (explicit / none / cut / packed) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for depth in depths_mm:
        values, events = {}, {}
        for label in ("explicit", "none", "cut", "packed"):
            m = sphere_model(label, pk, depth_mm=depth)
            c = m.dhr(0.0, 1, 0, 0, rays, MAX_EVENTS, MAX_INTERNAL, threads)
            t = c[3] / c[0]
            values[label], events[label] = (t, math.sqrt(t * (1 - t) / c[0])), c[5] / c[0]
        ref = values["explicit"][0]
        cells = [f"{depth:g} mm", fmt(*values["explicit"])]
        for label in ("none", "cut", "packed"):
            cells += [fmt(*values[label]), f"{100 * (values[label][0] / ref - 1):+.1f} %"]
        cells.append(" / ".join(f"{events[k]:.1f}" for k in ("explicit", "none", "cut", "packed")))
        lines.append("| " + " | ".join(cells) + " |")
        print("slab " + " | ".join(cells), flush=True)
    return lines


def wet_sand_rows(scale, threads):
    """The wet-beach preset (water-filled pores) with the classic model, `cut` and the explicit
    reference (default packing): where the surface-layer models put the water surface matters."""
    import warnings

    import sandlight

    rays = int(20_000 * scale)
    sample = SandSample.preset("wet-beach")
    lines = [
        "",
        f"Wet sand: the `wet-beach` preset (saturation {sample.saturation:g}), {rays:,} rays per run, "
        "default packing for the explicit reference.\n",
        "| model | ρ 450 nm | ρ 1450 nm (water band) |",
        "|---|---|---|",
    ]
    for label, kw in (("none", {}), ("cut", {"memory": "cut"}), ("explicit", {"geometry": "explicit"})):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # the wet-sand warning this row documents
            r = sandlight.reflectance(sample, [450.0, 1450.0], rays=rays, threads=threads, progress=False, **kw)
        lines.append(f"| {label} | " + " | ".join(fmt(v, e) for v, e in zip(r.values, r.stderr)) + " |")
        print(f"wet {label}: {r.values}", flush=True)
    return lines


def incidence_by_flight(
    pk, samples, seed=1, bins=((0, 0.01), (0.01, 0.03), (0.03, 0.06), (0.06, 0.12), (0.12, 0.25), (0.25, math.inf))
):
    """Flights through a packing of monodisperse spheres: from a uniform point on a random grain,
    in a Lambertian direction about its normal, to the first grain met (periodic images); per bin of
    flight length, the count and the mean cosine of the incidence angle on that grain."""
    centres, diameters = pk.particles()
    period = np.array(pk.period_mm)
    r = 0.5 * float(diameters[0])
    rng = np.random.default_rng(seed)
    lengths, cosines = np.empty(samples), np.empty(samples)
    for k in range(samples):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        o = centres[rng.integers(len(centres))] + n * r * (1 + 1e-9)
        mu, phi = math.sqrt(rng.random()), 2 * math.pi * rng.random()
        t1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        t1 /= np.linalg.norm(t1)
        d = n * mu + math.sqrt(1 - mu * mu) * (t1 * math.cos(phi) + np.cross(n, t1) * math.sin(phi))
        rel = centres - o
        rel -= period * np.round(rel / period)
        b = rel @ d
        c2 = np.einsum("ij,ij->i", rel, rel) - r * r
        disc = b * b - c2
        ahead = np.flatnonzero((disc > 0) & (b > 0) & (c2 > 1e-12))
        t = b[ahead] - np.sqrt(disc[ahead])
        j = int(np.argmin(t))
        lengths[k] = t[j]
        cosines[k] = -(d @ (d * t[j] - rel[ahead[j]])) / r
    return [
        ((lo, hi), int(sel.sum()), float(cosines[sel].mean()))
        for lo, hi in bins
        for sel in [(lengths >= lo) & (lengths < hi)]
    ]


def settled_report(pk, cut, d_mm, seed=9):
    """The surface layer of a packing against the cut packing it was deposited on (itself for
    the cut): surface heights; coverage (fraction of vertical lines that meet a deposited grain
    first, where the two surfaces differ); 0.25–1 grain above the cut plane the packing
    fraction and the fraction of points in two or more grains; and the overlap volume over the
    deposit's height range, relative to the deposited solid (NaN without a deposit)."""
    h = pk.period_mm[2]
    heights = pk.surface_heights(20_000, seed)
    covered = np.mean(heights != cut.surface_heights(20_000, seed))
    porosity, overlap = pk.porosity_profile(h + np.linspace(0.25, 1.0, 7) * d_mm, 50_000, seed)
    dep, d_dep = pk.deposited()
    dz = 0.02 * d_mm
    solid = np.sum(np.pi / 6 * d_dep**3)
    overlap_volume = np.nan
    if solid:
        _, overlap_all = pk.porosity_profile(np.arange((dep[:, 2] - d_dep).min(), pk.top_mm, dz), 5_000, seed)
        overlap_volume = overlap_all.sum() * dz * pk.period_mm[0] * pk.period_mm[1] / solid
    return {
        "n": pk.n_deposited,
        "top": pk.top_mm - h,
        "mean": heights.mean() - h,
        "sd": heights.std(),
        "min": heights.min() - h,
        "max": heights.max() - h,
        "covered": covered,
        "eta": 1.0 - porosity.mean(),
        "overlap": overlap.mean(),
        "overlap_volume": overlap_volume,
    }


def run_settled(scale, threads):
    """Explicit cut vs explicit settled vs on-the-fly (memory none, cut) for monodisperse
    spheres, and the settled layers of spheres (1, 2, 3 layers) and spheroids (2 layers)."""
    d, phi = 0.25, 0.40
    rays = {a: int(RAYS[a] * scale) for a in ALPHAS_PER_CM}
    rows, layers = [], {}
    for name, eps, counts in (("monodisperse spheres", 1.0, (1.0, 2.0, 3.0)), ("spheroids ε = 1.4", 1.4, (2.0,))):

        def make(alpha=0.0, mem="none", eps=eps):
            return grain_medium([d], aspect_ratio=eps, alpha_per_mm=alpha, porosity=phi, memory=mem)

        t0 = time.perf_counter()
        cut = generate_packing(make(), reference_mm=d, seed=1)
        t_cut = time.perf_counter() - t0
        if eps == 1.0:
            layers[(name, 0.0)] = settled_report(cut, cut, d) | {"t_cut": t_cut, "t_settled": np.nan}
        for n_layers in counts:
            t0 = time.perf_counter()
            settled = generate_packing(make(), reference_mm=d, seed=1, surface="settled", settled_layers=n_layers)
            t_settled = time.perf_counter() - t0
            layers[(name, n_layers)] = settled_report(settled, cut, d) | {"t_cut": t_cut, "t_settled": t_settled}
            if eps != 1.0 or n_layers != 2.0:
                continue
            for a in ALPHAS_PER_CM:
                alpha = a / 10.0
                out = {"label": f"α = {a:g} cm⁻¹"}
                out["explicit cut"] = dhr(make(alpha).explicit(cut), rays[a], threads)[:2]
                out["explicit settled"] = dhr(make(alpha).explicit(settled), rays[a], threads)[:2]
                for mem in ("none", "cut"):
                    out[mem] = dhr(make(alpha, mem), rays[a], threads)[:2]
                print(
                    f"settled {out['label']:>16s}  "
                    + "  ".join(f"{k} {v[0]:.4f}" for k, v in out.items() if k != "label"),
                    flush=True,
                )
                rows.append(out)
    body = (
        f"Generated by `scripts/studies/geometry_comparison.py --no-tables --settled --scale {scale:g}` on "
        f"{describe()}, "
        f"{time.strftime('%Y-%m-%d')}. Monodisperse spheres d = 0.25 mm, φ = 0.40, n = 1.544, one packing "
        "(seed 1, 4 × 4 × 8 mm) with its cut surface and with 2 reference-grain layers settled on it; normal "
        "incidence, directional-hemispherical reflectance ± one standard error; rays per α: "
        + ", ".join(f"{rays[a]:,} at {a:g} cm⁻¹" for a in ALPHAS_PER_CM)
        + ". Δ: relative to the explicit settled surface; ✗: outside issue 9's target (3 % or 0.002).\n\n"
        "| α | explicit cut | Δ | explicit settled | on-the-fly `none` | Δ | on-the-fly `cut` | Δ |\n"
        "|---|---|---|---|---|---|---|---|\n"
    )
    for r in rows:
        ref = r["explicit settled"][0]
        cells = [r["label"]]
        for key in ("explicit cut", "explicit settled", "none", "cut"):
            v = r[key][0]
            cells.append(fmt(*r[key]))
            if key != "explicit settled":
                cells.append(f"{100 * (v / ref - 1):+.1f} %" + ("" if within_target(v, ref) else " ✗"))
        body += "| " + " | ".join(cells) + " |\n"
    body += (
        "\nSettled layers (seed 1, same box; heights relative to the cut plane z = H in mm, from 20 000 vertical "
        "lines; covered: fraction of those lines that meet a deposited grain first; η and points in ≥ 2 grains: "
        "7 planes 0.25–1 grain above the cut plane, 50 000 points each; overlap volume: points in ≥ 2 grains "
        "over the deposit's height range, relative to the deposited solid; time: generating the cut packing, "
        "and the settled one with its deposit; 0 layers: the cut itself):\n\n"
        "| grains | layers | deposited | surface height mean ± sd | range | rays start at | covered | "
        "η of the layer | points in ≥ 2 grains | overlap volume | time cut / settled |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n"
    )
    for (name, n_layers), r in layers.items():
        volume = "–" if np.isnan(r["overlap_volume"]) else f"{r['overlap_volume']:.2e}"
        times = f"{r['t_cut']:.1f} s" + ("" if np.isnan(r["t_settled"]) else f" / {r['t_settled']:.1f} s")
        body += (
            f"| {name} | {n_layers:g} | {r['n']} | {r['mean']:+.3f} ± {r['sd']:.3f} | {r['min']:+.3f} … "
            f"{r['max']:+.3f} | {r['top']:+.3f} | {r['covered']:.4f} | {r['eta']:.4f} | {r['overlap']:.4f} | "
            f"{volume} | {times} |\n"
        )
    return body


def passed_line(rows):
    passed = {m: sum(within_target(r[m][0], r["explicit"][0]) for r in rows) for m in MEMORIES}
    return "Cases within the target: " + ", ".join(f"{m} {passed[m]}/{len(rows)}" for m in MEMORIES) + "."


def preset_packing(comp):
    """The explicit reference of a preset: its sand packed (seed 1), its fines on the fly."""
    return generate_packing(native_medium(comp, 550.0), reference_mm=reference_grain_mm(comp), seed=1)


def run_presets(scale, threads):
    """Every preset, dried, at PRESET_WAVELENGTHS_NM: explicit against on the fly."""
    rows, reports = [], {}
    for name in SandSample.presets():
        sample = SandSample.preset(name)
        label = name
        if sample.saturation > 0:
            # The surface-layer models are not validated for water-filled pores (docs/geometry.md).
            sample = SandSample.from_dict({**sample.to_dict(), "saturation": 0.0})
            label = f"{name} (dried)"
        comp = compose(sample)
        pk = preset_packing(comp)
        reports[label] = packing_report(
            pk, medium=native_medium(comp, 650.0), threads=threads, rays=int(100_000 * scale)
        )
        for lam in PRESET_WAVELENGTHS_NM:
            rows.append(
                run_case(
                    label,
                    lambda mem, lam=lam, comp=comp: native_medium(comp, lam, memory=mem),
                    pk,
                    int(RAYS["preset"] * scale),
                    threads,
                    f"{label}, {lam:.0f} nm",
                )
            )
    return (
        f"Generated by `scripts/studies/geometry_comparison.py --presets --scale {scale:g}` on {describe()}, "
        f"{time.strftime('%Y-%m-%d')}. Dry, normal incidence; columns as in the main table.\n\n"
        + table(rows)
        + "\n"
        + passed_line(rows)
        + "\n\nPackings (seed 1; rays deeper than H at 650 nm):\n\n"
        + packing_table(reports)
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=float, default=1.0, help="multiplies every ray count")
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--brdf", action="store_true", help="also measure principal-plane BRDFs")
    ap.add_argument("--no-tables", action="store_true", help="skip the main tables")
    ap.add_argument(
        "--diagnostics", action="store_true", help="also the diagnostics: escape by scattering order, grains with fines"
    )
    ap.add_argument("--settled", action="store_true", help="also compare the cut and the settled surface")
    ap.add_argument("--presets", action="store_true", help="also compare every preset, dried, at four wavelengths")
    args = ap.parse_args(argv)
    started = time.perf_counter()
    d = 0.25
    phi = 0.40
    poly_q = SizeDistribution("lognormal", 0.05, 2.0, median_mm=d, spread=1.4).encounter_quantiles()
    grains = {
        "monodisperse spheres": dict(q=[d], eps=1.0),
        "polydisperse spheres (σ_g = 1.4)": dict(q=poly_q, eps=1.0),
        "spheroids ε = 1.4": dict(q=[d], eps=1.4),
    }
    rows, reports = [], {}
    text = DOC.read_text(encoding="utf-8") if DOC.exists() else "# Explicit geometry and path memory\n"
    mono_packing = None
    if not args.no_tables:
        for name, g in grains.items():

            def make(mem, alpha=0.0, g=g):
                return grain_medium(g["q"], aspect_ratio=g["eps"], alpha_per_mm=alpha, porosity=phi, memory=mem)

            pk = generate_packing(make("none"), reference_mm=d, seed=1)
            mono_packing = mono_packing or pk
            reports[name] = packing_report(
                pk,
                d if g["eps"] == 1.0 and len(g["q"]) == 1 else None,
                phi,
                make("none", 0.05),
                args.threads,
                int(100_000 * args.scale),
            )
            for a in ALPHAS_PER_CM:
                rows.append(
                    run_case(
                        name,
                        lambda mem, a=a, make=make: make(mem, a / 10.0),
                        pk,
                        int(RAYS[a] * args.scale),
                        args.threads,
                        f"{name}, α = {a:g} cm⁻¹",
                    )
                )
        comp = compose(SandSample.preset("red-dune"))
        pk = preset_packing(comp)
        reports["red-dune (sand packed; silt, clay on the fly)"] = packing_report(
            pk, medium=native_medium(comp, 650.0), threads=args.threads, rays=int(100_000 * args.scale)
        )
        for lam in (450.0, 550.0, 650.0):
            rows.append(
                run_case(
                    "red-dune",
                    lambda mem, lam=lam: native_medium(comp, lam, memory=mem),
                    pk,
                    int(RAYS["preset"] * args.scale),
                    args.threads,
                    f"red-dune, {lam:.0f} nm",
                )
            )
        body = (
            f"Generated by `scripts/studies/geometry_comparison.py --scale {args.scale:g}` on {describe()}, "
            f"{time.strftime('%Y-%m-%d')}. Normal incidence, directional-hemispherical reflectance, "
            "± one standard error √(ρ(1 − ρ)/N). Δ: on-the-fly relative to explicit; ✗: outside the target "
            "(3 % relative or 0.002 absolute, whichever is larger).\n\n"
            + table(rows)
            + "\n"
            + passed_line(rows)
            + "\n\n"
            "Packings (seed 1; φ (points): fraction of 200 000 random points in no packed grain; overlap "
            "volume: fraction in two or more; rays deeper than H: fraction of rays at α = 0.5 cm⁻¹ "
            "(red-dune: 650 nm) that get more than one box period H below the cut plane):\n\n" + packing_table(reports)
        )
        text = replace_block(text, BEGIN, END, body)
        write_atomic(DOC, text)
        print(body)
    if args.brdf:
        if mono_packing is None:
            mono_packing = generate_packing(grain_medium([d], porosity=phi), reference_mm=d, seed=1)
        text = DOC.read_text(encoding="utf-8") if DOC.exists() else text
        text = replace_block(text, BRDF_BEGIN, BRDF_END, run_brdf(args.scale, args.threads, mono_packing))
        write_atomic(DOC, text)
    if args.diagnostics:
        body = run_diagnostics(args.scale, args.threads)
        text = replace_block(DOC.read_text(encoding="utf-8"), DIAG_BEGIN, DIAG_END, body)
        write_atomic(DOC, text)
    if args.settled:
        body = run_settled(args.scale, args.threads)
        text = DOC.read_text(encoding="utf-8") if DOC.exists() else text
        write_atomic(DOC, replace_block(text, SETTLED_BEGIN, SETTLED_END, body))
        print(body)
    if args.presets:
        body = run_presets(args.scale, args.threads)
        write_atomic(DOC, replace_block(DOC.read_text(encoding="utf-8"), PRESETS_BEGIN, PRESETS_END, body))
        print(body)
    print(f"done in {time.perf_counter() - started:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
