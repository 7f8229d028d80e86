"""Everything the command line prints goes through this module.

Most of what a command prints is not sandlight's own text: values, paths, names, messages that
quote them, and what was read from files (sample files, model names, scene names). So text is
printed as plain text only:

- never parsed as rich markup: ``[/]`` in a file name made rich raise ``MarkupError``,
  ``[link=…]x[/link]`` showed as ``x``, and "outside the [sample] table" lost its ``[sample]``;
- never highlighted: rich's automatic highlighting coloured the digits inside names
  ("Hematite.02");
- stripped of control characters: a model name holding ``ESC[2J`` cleared the user's screen.

The few styles (the red ``error:``, the yellow ``warning:``) are applied here, to our own words.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import NoReturn

import typer
from rich.console import Console, RenderableType
from rich.table import Table
from rich.text import Text

from sandlight.checks import CONTROL_CHARACTERS

# Consoles without markup, highlighting or emoji codes; soft wrap keeps a long message on one
# logical line (the terminal wraps it) instead of breaking it where rich guesses the width.
_stdout = Console(markup=False, highlight=False, emoji=False, soft_wrap=True)
_stderr = Console(stderr=True, markup=False, highlight=False, emoji=False, soft_wrap=True)


def printable(text: object) -> str:
    """``str(text)`` without control characters (`sandlight.checks.CONTROL_CHARACTERS`)."""
    return CONTROL_CHARACTERS.sub("", str(text))


def echo(message: object, *, err: bool = False) -> None:
    """Print one message as plain text (to stderr with ``err``)."""
    (_stderr if err else _stdout).print(Text(printable(message)))


def error(message: object) -> None:
    """Print ``error: message`` to stderr."""
    _stderr.print(Text.assemble(("error: ", "bold red"), printable(message)))


def warning(message: object) -> None:
    """Print ``warning: message`` to stderr."""
    _stderr.print(Text.assemble(("warning: ", "yellow"), printable(message)))


def fail(message: object, code: int = 2) -> NoReturn:
    """Print ``error: message`` and end the command with exit ``code`` (2: bad input)."""
    error(message)
    raise typer.Exit(code)


def table(columns: Sequence[str], rows: Iterable[Sequence[object]], *, title: object = None) -> None:
    """Print a table of plain-text cells, right-aligned (they are numbers)."""
    shown = Table(title=None if title is None else Text(printable(title)))
    for column in columns:
        shown.add_column(column, justify="right")
    for row in rows:
        shown.add_row(*(Text(printable(cell)) for cell in row))
    _stdout.print(shown)


def show(renderable: RenderableType) -> None:
    """Print a rich renderable made by sandlight (e.g. a report's table); a string is plain text."""
    _stdout.print(Text(printable(renderable)) if isinstance(renderable, str) else renderable)


def show_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: object = None,
    line: str | None = None,
) -> None:
    """`warnings.showwarning` of the command line: one ``warning: message`` line, without the
    file, line number and source line Python prints by default."""
    warning(message)
