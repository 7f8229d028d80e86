"""Exception hierarchy of sandlight.

Every error raised on bad input names the parameter, the value and what is allowed.
"""

#: Longest text of a name or value that an error message quotes: a value can be anything the
#: user passed (a 50 MB string), and a message must stay one readable line.
MAX_QUOTED = 200


def _shortened(text: str) -> str:
    """``text`` cut to `MAX_QUOTED` characters, its full length stated."""
    if len(text) <= MAX_QUOTED:
        return text
    return f"{text[:MAX_QUOTED]}… ({len(text):,} characters in all)"


def quoted(value: object) -> str:
    """The repr of ``value`` for a message: at most about `MAX_QUOTED` characters, with an
    ellipsis and the original length when cut. Long strings are cut before the repr is made."""
    if isinstance(value, (str, bytes)) and len(value) > MAX_QUOTED:
        unit = "characters" if isinstance(value, str) else "bytes"
        return f"{value[:MAX_QUOTED]!r}… ({len(value):,} {unit} in all)"
    return _shortened(repr(value))


class SandlightError(Exception):
    """Base class of every error sandlight raises on purpose."""


class ParameterError(SandlightError, ValueError):
    """A parameter is missing, non-numeric, NaN, out of its domain or inconsistent.

    ``name``, ``value`` and ``allowed`` are kept whole as attributes; the message quotes the
    name and the value shortened to about `MAX_QUOTED` characters each.
    """

    def __init__(self, name: str, value: object, allowed: str) -> None:
        self.name = name
        self.value = value
        self.allowed = allowed
        super().__init__(f"{_shortened(str(name))} = {quoted(value)} is not allowed: {allowed}")


class ModelFileError(SandlightError, OSError):
    """A model or data file is missing, truncated, corrupt or not a sandlight file."""


class Cancelled(SandlightError, KeyboardInterrupt):
    """A long run was stopped by the user (Ctrl-C)."""
