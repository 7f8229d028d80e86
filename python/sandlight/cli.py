"""Command-line interface (typer). The physics never imports this module."""

import typer

app = typer.Typer(no_args_is_help=True, add_completion=False,
                  help="sandlight: the appearance of sand from its mineralogy.")


@app.callback()
def _root() -> None:
    """sandlight: the appearance of sand from its mineralogy."""


def main() -> None:
    app()
