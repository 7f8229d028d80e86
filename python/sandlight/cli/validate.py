"""Command `sandlight validate`: the model against measured spectra, written to a Markdown report."""

from __future__ import annotations

from pathlib import Path

import typer

from sandlight.checks import check_count
from sandlight.cli._app import app
from sandlight.cli._common import COUNT_FORM, SEED_HELP
from sandlight.cli._output import echo
from sandlight.io import check_output_directory, check_output_file

#: The report by default: a new folder in the working directory (it was docs/validation.md, so a
#: run from a checkout overwrote the shipped docs).
DEFAULT_REPORT = Path("sandlight-validation") / "validation.md"


@app.command()
def validate(
    rays: str = typer.Option("1e5", "--rays", "-n", help=f"Rays per wavelength for the validation runs, {COUNT_FORM}."),
    output: Path = typer.Option(
        DEFAULT_REPORT,
        "-o",
        "--output",
        help="The Markdown report (.md; its folder is created). An existing report is overwritten between its "
        "BEGIN/END markers, the text outside them kept.",
    ),
    figures: Path | None = typer.Option(
        None,
        "--figures",
        help="Folder for the PNG plots (default: img beside the report; created; plots overwritten).",
    ),
    sample: list[str] | None = typer.Option(
        None,
        "--sample",
        help="Validate only this validation sample, by USGS name, spectrum or preset (e.g. ottawa-gds74; "
        "repeatable; default: all).",
    ),
    variant_rays: str | None = typer.Option(
        None,
        "--variant-rays",
        help=f"Rays per wavelength for the diagnostic variants and Figure 3, {COUNT_FORM} (default: --rays / 5).",
    ),
    no_variants: bool = typer.Option(False, "--no-variants", help="Skip the diagnostic variants and Figure 3."),
    seed: int = typer.Option(0, "--seed", help=SEED_HELP),
) -> None:
    """Run the model for the USGS validation samples (presets set from the sample descriptions,
    never fitted), score it against the measured spectra (RMS and maximum error over 400–700 and
    400–2500 nm, with Monte Carlo error bars), plot model vs measurement, and write the report."""
    import shlex

    from sandlight import validation as v

    figures = output.parent / "img" if figures is None else figures
    check_output_file(output, "--output", (".md",), make_dirs=True)
    check_output_directory(figures, "--figures")
    n = check_count("--rays", rays)
    nv = check_count("--variant-rays", variant_rays) if variant_rays is not None else max(1, n // 5)
    results = v.validate(sample or None, rays=n, seed=seed, progress=True)
    fig_paths = []
    for r in results:
        p = figures / f"validation-{r.sample.preset}.png"
        r.plot(p)
        fig_paths.append(p)
        for e in r.errors.values():
            echo(
                f"{r.sample.name:32s} {e.band:12s} RMS {e.rms:.4f} ± {e.rms_mc:.4f} "
                f"(target ≤ {e.target_rms:g}: {e.verdict}), max |error| {e.max_abs:.4f} at {e.max_at_nm:g} nm"
            )
    variants = spectra = f3 = None
    if not no_variants:
        names = {r.sample.name for r in results}
        chosen = [x for x in v.DIAGNOSTIC_VARIANTS if x.sample in names]
        echo(f"diagnostic variants: {len(chosen)} runs at {nv:,} rays per wavelength")
        variants = v.run_variants(chosen, rays=nv, seed=seed, progress=True)
        echo(f"Figure 3: {nv:,} rays per wavelength")
        spectra = v.figure3_spectra(rays=nv, seed=seed, progress=True)
        f3 = figures / "validation-figure3.png"
        v.plot_figure3(spectra, f3)
    args = ["--rays", rays, "-o", str(output), "--figures", str(figures)]
    args += [a for s in (sample or []) for a in ("--sample", s)]
    args += ["--no-variants"] if no_variants else (["--variant-rays", variant_rays] if variant_rays else [])
    args += ["--seed", str(seed)] if seed else []
    command = "sandlight validate " + " ".join(shlex.quote(a) for a in args)
    v.write_report(
        output,
        results,
        figure_paths=fig_paths,
        command=command,
        variants=variants,
        figure3_path=f3,
        figure3=spectra,
    )
    echo(f"wrote {output} and {len(fig_paths) + (f3 is not None)} figures in {figures}")
