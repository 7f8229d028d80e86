"""Exception hierarchy of sandlight.

Every error raised on bad input names the parameter, the value and what is allowed.
"""


class SandlightError(Exception):
    """Base class of every error sandlight raises on purpose."""


class ParameterError(SandlightError, ValueError):
    """A parameter is missing, non-numeric, NaN, out of its domain or inconsistent."""

    def __init__(self, name: str, value, allowed: str):
        self.name = name
        self.value = value
        self.allowed = allowed
        super().__init__(f"{name} = {value!r} is not allowed: {allowed}")


class ModelFileError(SandlightError, OSError):
    """A model or data file is missing, truncated, corrupt or not a sandlight file."""


class Cancelled(SandlightError, KeyboardInterrupt):
    """A long run was stopped by the user (Ctrl-C)."""
