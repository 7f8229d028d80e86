"""The typer application object shared by every command module."""

import typer

app = typer.Typer(
    no_args_is_help=True, add_completion=False, help="sandlight: the appearance of sand from its mineralogy."
)
