"""Command-line interface. Each area registers its commands on the shared typer app in its own
module; importing them here is what makes the commands exist. The physics never imports this
package."""

from sandlight.cli import colour as _colour  # noqa: F401,E402

# Command modules (one per area); imported for their @app.command() side effect.
from sandlight.cli import engine as _engine  # noqa: F401,E402
from sandlight.cli import fit as _fit  # noqa: F401,E402
from sandlight.cli import gonio as _gonio  # noqa: F401,E402
from sandlight.cli import predict as _predict  # noqa: F401,E402
from sandlight.cli import render as _render  # noqa: F401,E402
from sandlight.cli import serve as _serve  # noqa: F401,E402
from sandlight.cli import sky as _sky  # noqa: F401,E402
from sandlight.cli import spatial as _spatial  # noqa: F401,E402
from sandlight.cli import validate as _validate  # noqa: F401,E402
from sandlight.cli._app import app


def main() -> None:
    app()
