"""Command of the rendering area: ``sandlight render SCENE -o frames/ [--video out.mp4]``.

SCENE is a shipped scene (``desert-day``, ``beach-drying``) or the path of a scene TOML file; the
options override the file's resolution, frame count, samples, seed and threads. Bad values exit
with code 2 and a one-line message naming the key; Ctrl-C exits with 130 keeping finished frames.
"""

from __future__ import annotations

from pathlib import Path

import typer

from sandlight.cli._app import app
from sandlight.cli._common import SEED_HELP, THREADS_HELP, option_names
from sandlight.cli._output import echo
from sandlight.errors import ParameterError
from sandlight.io import check_output_directory, check_output_file


@app.command()
def render(
    scene: str = typer.Argument(..., help="A shipped scene (desert-day, beach-drying) or a scene TOML file."),
    output: Path = typer.Option(
        ..., "--output", "-o", help="Folder for the frames (PNG and linear NetCDF; created, frames overwritten)."
    ),
    video: Path | None = typer.Option(
        None, "--video", help="Also encode the frames as this MP4 file (.mp4, overwritten if it exists)."
    ),
    width: int | None = typer.Option(None, help="Image width in pixels, 1–16384 (overrides output.width)."),
    height: int | None = typer.Option(None, help="Image height in pixels, 1–16384 (overrides output.height)."),
    frames: int | None = typer.Option(None, help="Number of frames, 1–100000 (overrides output.frames)."),
    spp: int | None = typer.Option(None, help="Samples per pixel, ≥ 1 (overrides render.spp)."),
    seed: int | None = typer.Option(None, help=f"{SEED_HELP} Overrides render.seed."),
    threads: int | None = typer.Option(None, help=THREADS_HELP),
    linear: str | None = typer.Option(
        None,
        "--linear",
        help="Per-frame NetCDF: 'spectral' (radiance and XYZ), 'xyz' or 'none' (overrides output.linear).",
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar with an ETA."),
    renderer: str = typer.Option(
        "sandlight", help="'sandlight' (the spectral path tracer) or 'mitsuba' (Mitsuba 3, docs/mitsuba.md)."
    ),
) -> None:
    """Render an animation of a sandy landscape under the sun and sky (paper §4.2): frames as
    sRGB PNG and linear NetCDF (XYZ, and with --linear spectral the spectral radiance),
    optionally an MP4."""
    from sandlight.render.animation import render_scene
    from sandlight.render.scene import Scene

    check_output_directory(output, "--output")
    if video is not None:
        check_output_file(video, "--video", (".mp4",), make_dirs=True)
    overrides = {"width", "height", "frames", "spp", "seed", "threads", "linear"}
    with option_names({name: f"--{name}" for name in overrides}):
        parsed = Scene.load(scene).with_overrides(
            width=width, height=height, frames=frames, spp=spp, seed=seed, threads=threads, write_linear=linear
        )
    if renderer not in ("sandlight", "mitsuba"):
        raise ParameterError("--renderer", renderer, "'sandlight' or 'mitsuba'")
    try:
        if renderer == "mitsuba":
            from sandlight.mitsuba.animation import render_scene_mitsuba

            run = render_scene_mitsuba(parsed, output, video=video, log=echo)
        else:
            run = render_scene(parsed, output, video=video, progress=progress, log=echo)
    except KeyboardInterrupt:
        kept = len(list(Path(output).glob("frame_*.png")))
        echo(f"interrupted: the {kept} finished frame(s) in {output} are complete; no video was written", err=True)
        raise typer.Exit(130) from None
    total = sum(run.render_seconds)
    echo(
        f"{len(run.pngs)} frame(s) in {output} ({total:.1f} s rendering, {run.elapsed_s:.1f} s in all)"
        + (f"; video {run.video}" if run.video else "")
    )
