"""Command of the web area: ``sandlight serve`` starts the sand explorer (docs/explorer.md)."""

from __future__ import annotations

import typer

from sandlight.cli._app import app
from sandlight.cli._output import echo, warning


@app.command()
def serve(
    port: int = typer.Option(8765, help="TCP port, 0–65535 (0: any free port)."),
    host: str = typer.Option(
        "127.0.0.1",
        help="Address to bind. Only loopback addresses (127.0.0.1, ::1, localhost) unless --allow-remote is given.",
    ),
    allow_remote: bool = typer.Option(
        False,
        "--allow-remote",
        help="Allow a non-loopback --host: the explorer is then reachable from other machines, without authentication.",
    ),
    open_browser: bool = typer.Option(True, "--open/--no-open", help="Open the page in the default web browser."),
) -> None:
    """Start the sand explorer: a local web page to explore sand with sliders (Ctrl-C stops it)."""
    from sandlight.web.server import serve as run

    run(host, port, allow_remote=allow_remote, open_browser=open_browser, warn=warning, say=echo)
