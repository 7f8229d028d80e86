"""The typer application object shared by every command module, and what every command runs
inside: sandlight's errors become one-line messages and exit codes, warnings one line each."""

from __future__ import annotations

import warnings
from typing import Any

import click
import typer
from typer.core import TyperGroup

from sandlight.cli._output import echo, error, show_warning
from sandlight.errors import Cancelled, ParameterError, SandlightError


def exit_code(exc: BaseException) -> int:
    """The exit code of a command stopped by ``exc``: 130 interrupted, 2 bad input (a value, a
    path, a file, a job store: ParameterError, OSError, JobError), 1 anything else sandlight
    refuses (a model or module missing from this installation)."""
    from sandlight.jobs.errors import JobError

    if isinstance(exc, KeyboardInterrupt):
        return 130
    return 2 if isinstance(exc, (ParameterError, OSError, JobError)) else 1


def _without_placeholder(option: click.Parameter | None) -> Any:
    # typer's help shows a flag's type as "<bool>", as if it took a value; an empty metavar
    # shows nothing.
    if option is not None and getattr(option, "is_flag", False):
        option.metavar = ""
    return option


def _without_flag_placeholders(command: click.Command) -> None:
    """The help of ``command`` without "<bool>" beside its flags (and its --help)."""
    for param in command.params:
        _without_placeholder(param)
    own = command.get_help_option
    command.get_help_option = lambda ctx: _without_placeholder(own(ctx))  # type: ignore[method-assign]


class _Commands(TyperGroup):
    """Runs each command with plain one-line warnings and turns sandlight's errors, OS errors
    (a directory where a file was expected, a read-only directory) and Ctrl-C into a message
    and an exit code instead of a traceback."""

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        command = super().get_command(ctx, cmd_name)
        if command is not None:
            _without_flag_placeholders(command)
        return command

    def get_help_option(self, ctx: click.Context) -> click.Option | None:
        return _without_placeholder(super().get_help_option(ctx))

    def invoke(self, ctx: click.Context) -> Any:
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            try:
                return super().invoke(ctx)
            except Cancelled as exc:
                echo(f"interrupted: {exc}", err=True)
                raise typer.Exit(exit_code(exc)) from None
            except KeyboardInterrupt as exc:
                echo("interrupted: every file written so far is complete; nothing else was written", err=True)
                raise typer.Exit(exit_code(exc)) from None
            except (SandlightError, OSError) as exc:
                error(exc)
                raise typer.Exit(exit_code(exc)) from None


app = typer.Typer(
    cls=_Commands,
    no_args_is_help=True,
    add_completion=False,
    help="sandlight: the appearance of sand from its mineralogy.",
)
