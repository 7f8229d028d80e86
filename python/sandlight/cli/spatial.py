"""Commands of the spatial predictor and the explicit BRDF: train-spatial, appearance."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer

from sandlight.checks import check_choice, check_count
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    ENGINE_OPTIONS,
    PRESET_HELP,
    SEED_HELP,
    WAVELENGTH_HELP,
    MemoryOption,
    PresetOption,
    SampleFileArgument,
    SlicesOption,
    StacksOption,
    load_sample,
    option_names,
)
from sandlight.cli._output import echo, show
from sandlight.io import check_output_directory, check_output_file


def _axis(text: str):
    """``NAME=start:stop:count`` (count points, ends included) or ``NAME=v1,v2,...``."""
    from sandlight.errors import ParameterError

    name, sep, values = text.partition("=")
    if not sep or not name.strip():
        raise ParameterError("--axis", text, "NAME=start:stop:count or NAME=v1,v2,... (e.g. saturation=0:1:16)")
    try:
        if ":" in values:
            start, stop, n = values.split(":")
            if float(n) != int(float(n)) or int(float(n)) < 2:
                raise ValueError
            return name.strip(), np.linspace(float(start), float(stop), int(float(n)))
        return name.strip(), np.array([float(v) for v in values.split(",")])
    except ValueError:
        raise ParameterError("--axis", text, "NAME=start:stop:count with count >= 2, or NAME=v1,v2,...") from None


def _point(text: str) -> dict:
    """``NAME=VALUE[,NAME=VALUE...]``."""
    from sandlight.errors import ParameterError

    try:
        return {k.strip(): float(v) for k, v in (item.split("=") for item in text.split(","))}
    except ValueError:
        raise ParameterError("--holdout", text, "NAME=VALUE[,NAME=VALUE...] (e.g. saturation=0.5)") from None


def _nodes_file(path: Path):
    """Scattered nodes from a CSV file whose header names the parameters."""
    from sandlight.errors import ParameterError

    try:
        with open(path, encoding="utf-8") as fh:
            header = [h.strip() for h in fh.readline().split(",")]
        values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as exc:
        raise ParameterError(
            "--nodes", str(path), f"a readable CSV file with a header of parameter names ({exc})"
        ) from None
    return tuple(header), values


@app.command("train-spatial")
def train_spatial_command(
    sample_file: Path | None = typer.Argument(
        None, help="Base sample (TOML/JSON) giving the parameters the mesh does not vary (default: SandSample())."
    ),
    preset: str | None = typer.Option(None, "--preset", help=f"Base sample: {PRESET_HELP[0].lower()}{PRESET_HELP[1:]}"),
    out: Path = typer.Option(
        ...,
        "-o",
        "--output",
        "--out",
        help="Output directory: job stores (resumed), model and report (overwritten).",
    ),
    axis: list[str] = typer.Option(
        None,
        "--axis",
        help="Grid axis NAME=start:stop:count or NAME=v1,v2,... "
        "(repeatable; default saturation=0:1:16, the paper's beach scene).",
    ),
    nodes: Path | None = typer.Option(
        None, "--nodes", help="Scattered nodes: CSV with a header of parameter names (instead of --axis)."
    ),
    rays: str = typer.Option("1e7", "--rays", "-n", help=f"Goniophotometer trials per node, {COUNT_FORM}."),
    wavelength: float = typer.Option(
        550.0, "--wavelengths", "--wavelength", "-w", help=f"{WAVELENGTH_HELP} The wavelength of the measurements."
    ),
    seed: int = typer.Option(0, "--seed", help=f"{SEED_HELP} It sets every node's engine seed."),
    holdout: list[str] = typer.Option(
        None,
        "--holdout",
        help="Held-out point NAME=VALUE[,NAME=VALUE] measured and compared with the prediction (repeatable).",
    ),
    holdout_rays: str | None = typer.Option(
        None, "--holdout-rays", help=f"Trials per held-out point, {COUNT_FORM} (default: --rays)."
    ),
    stacks: StacksOption = 31,
    slices: SlicesOption = 30,
    method: str = typer.Option(
        "average", "--method", help="Reduction of the counts to a BRDF: average (the paper) or pooled."
    ),
    threads: int = typer.Option(
        1, "--threads", help="Engine threads per node, ≥ 1 (nodes run side by side); results do not depend on it."
    ),
    workers: int | None = typer.Option(
        None, "--workers", help="Local worker processes (1: in-process) (default: one per CPU)."
    ),
    dask_local: int | None = typer.Option(None, "--dask-local", help="Start a Dask LocalCluster of N workers."),
    scheduler: str | None = typer.Option(None, "--scheduler", help="Dask scheduler address, tcp://HOST:PORT."),
    components: int | None = typer.Option(
        None, "--components", help="Principal components ℓ (default: by --variance)."
    ),
    variance: float = typer.Option(
        0.999, "--variance", help="Signal-variance threshold in (0, 1]: the fewest components ℓ reaching it."
    ),
    scaling: str = typer.Option(
        "relative", "--scaling", help="Scaling of the values before the PCA: relative, none (the paper) or noise."
    ),
    fit_only: bool = typer.Option(False, "--fit-only", help="Only refit from the complete datasets in --out."),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar with an ETA."),
    memory: MemoryOption = None,
) -> None:
    """Measure the BRDF at every mesh node and fit the spatial predictor (paper §3.2).

    Resumable: run the same command again to continue after an interruption."""
    from sandlight.jobs import make_executor
    from sandlight.sample import SandSample
    from sandlight.spatial import Mesh, train_spatial

    check_output_directory(out, "--output")
    base = load_sample(sample_file, preset, default=SandSample())
    if nodes is not None:
        if axis:
            from sandlight.errors import ParameterError

            raise ParameterError("--axis/--nodes", "both", "a grid (--axis) or scattered nodes (--nodes), not both")
        names, values = _nodes_file(nodes)
        mesh = Mesh(names, values, base)
    else:
        mesh = Mesh.grid(base, **dict(_axis(a) for a in (axis or ["saturation=0:1:16"])))
    points = [_point(h) for h in holdout or []]
    missing = [p for p in points if set(p) != set(mesh.parameters)]
    if missing:
        from sandlight.errors import ParameterError

        raise ParameterError("--holdout", missing[0], f"a value for each mesh parameter {mesh.parameters}")
    executor = None if fit_only else make_executor(workers, dask_local, scheduler)
    n = check_count("--rays", rays)
    with option_names({**ENGINE_OPTIONS, "variance_threshold": "--variance", "n_components": "--components"}):
        run = train_spatial(
            out,
            mesh,
            n,
            wavelength,
            seed,
            holdout=[[p[k] for k in mesh.parameters] for p in points],
            holdout_rays=None if holdout_rays is None else check_count("--holdout-rays", holdout_rays),
            stacks=stacks,
            slices=slices,
            method=method,
            executor=executor,
            threads=threads,
            checkpoint=scheduler is None,
            fit_only=fit_only,
            progress=progress,
            memory=memory,
            model_params={"n_components": components, "variance_threshold": variance, "scaling": scaling},
        )
    if not run.complete:
        echo(f"stopped with {run.nodes.n_done}/{run.nodes.n_total} nodes: run again to continue")
        raise typer.Exit(1)
    model = run.model
    ratio = model.explained_variance_ratio_
    signal = model.signal_variance_ratio_
    ell = model.n_components_
    echo(f"mesh: {mesh}")
    echo(f"engine memory {model.memory_!r}")
    echo(
        f"principal components: ℓ = {ell}; explained variance {ratio[:ell].sum():.5%}"
        + ("" if signal is None else f", signal variance {signal[:ell].sum():.5%}")
    )
    noise = "" if model.node_noise_rms_ is None else f" (node noise RMS {model.node_noise_rms_:.4g} sr⁻¹)"
    echo(f"reconstruction RMS {model.reconstruction_rms_:.4g} sr⁻¹{noise}")
    for report in run.reports:
        show(report.table())
    echo(f"times: measurement {run.measurement_s:.1f} s (this run), fit {run.fit_s:.2f} s")
    echo(f"model: {run.model_path}")


@app.command()
def appearance(
    sample_file: SampleFileArgument = None,
    preset: PresetOption = None,
    table: Path | None = typer.Option(
        None,
        "-o",
        "--output",
        "--table",
        help="Write the BRDF table (.nc: NetCDF, format sandlight-brdf-table; overwritten if it exists).",
    ),
    n_mu: int = typer.Option(32, "--n-mu", help="Table points in cos θ_i and cos θ_o, 2–4096 (uniform on [0, 1])."),
    n_dphi: int = typer.Option(32, "--n-dphi", help="Table points in Δφ, 2–4096 (uniform on [0, π] radians)."),
    spectral_model: Path | None = typer.Option(
        None, "--spectral-model", help="Spectral model file (default: the shipped ones, as --mode says)."
    ),
    mode: str = typer.Option(
        "paper",
        "--mode",
        help="Which shipped spectral models give r(λ): paper (400-700 nm every 20 nm) or full-range "
        "(350-2500 nm every 25 nm).",
    ),
    spatial_model: Path | None = typer.Option(
        None, "--spatial-model", help="Spatial model file (default: the shipped model that covers the sample)."
    ),
    combination: str = typer.Option(
        "energy", "--combination", help="energy (default) or product (the paper's formula, may exceed unit albedo)."
    ),
    shape: str = typer.Option(
        "reflectance",
        "--shape",
        help="reflectance (default: at each wavelength the BRDF shape at the sand's reflectance there, for "
        "spatial models that interpolate in it) or fixed (one shape at every wavelength, the paper's).",
    ),
) -> None:
    """The explicit spectral BRDF of a sample (paper §3.3): albedo summary and NetCDF table export."""
    import warnings

    from sandlight.appearance import SandAppearance
    from sandlight.errors import ParameterError
    from sandlight.predictor.prediction import answering_bank
    from sandlight.spatial import SpatialApproximationWarning

    if table is not None:
        check_output_file(table, "--output", (".nc",), make_dirs=True)
    check_choice("--mode", mode, ("paper", "full-range"))
    if spectral_model is not None and mode != "paper":
        raise ParameterError("--mode", mode, "paper (the default) with --spectral-model, which gives r(λ) itself")
    sample = load_sample(sample_file, preset)
    spectral = spectral_model if spectral_model is not None else answering_bank(None, mode)
    with warnings.catch_warnings():
        warnings.simplefilter("always", SpatialApproximationWarning)  # shown on every run, as one line
        with option_names({"combination": "--combination", "shape": "--shape"}):
            app_ = SandAppearance(sample, spectral, spatial_model, combination=combination, shape=shape)
    angles = np.array([0.0, 30.0, 60.0, 80.0, 89.0])
    t = np.radians(angles)
    albedo = app_.albedo(np.stack([np.sin(t), 0 * t, np.cos(t)], axis=1))
    wl = app_.wavelengths_nm
    pick = np.unique(np.linspace(0, len(wl) - 1, min(4, len(wl))).round().astype(int))
    echo(f"{app_}")
    echo("albedo (directional-hemispherical reflectance) by incidence:")
    echo("  θ_i  " + "".join(f"{wl[i]:>9g} nm" for i in pick))
    for a, row in zip(angles, albedo):
        echo(f"  {a:4g}°" + "".join(f"{row[i]:>12.4f}" for i in pick))
    if table is not None:
        with option_names({"n_mu": "--n-mu", "n_dphi": "--n-dphi", "n_mu, n_dphi": "--n-mu, --n-dphi"}):
            app_.to_table(table, n_mu, n_dphi)
        echo(f"wrote {table} ({len(wl)} wavelengths × {n_mu} × {n_mu} × {n_dphi})")
