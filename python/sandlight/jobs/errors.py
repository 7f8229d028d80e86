"""Errors of the job runner."""

from __future__ import annotations

import os

from sandlight.errors import SandlightError


class JobError(SandlightError):
    """A job cannot run, or some of its tasks failed after every retry.

    The results of the tasks that did succeed are in the store; running the job again retries
    only the missing ones.
    """


class JobSettingsError(JobError, ValueError):
    """A job store was made with settings that differ from the ones of this run.

    Attributes
    ----------
    setting : str
        Dotted path of the first differing setting (e.g. ``"rays"`` or ``"domain.forms"``).
    stored, requested
        Its value in the store and in this run.
    """

    def __init__(self, store: str | os.PathLike, setting: str, stored: object, requested: object) -> None:
        self.setting = setting
        self.stored = stored
        self.requested = requested
        super().__init__(
            f"the job store {store} was made with {setting} = {stored!r}, but this run asks for "
            f"{setting} = {requested!r}; use the original settings to resume it, or another "
            f"output directory to start a new job"
        )
