"""The one progress display of sandlight: every long computation reports through `progress_bar`.

On a terminal it is a rich bar: description, bar, count, rate, elapsed time and ETA. When the
output is not a terminal (a log file, a batch job) a bar would print nothing or escape codes, so
a plain line with the same figures is printed every `PLAIN_EVERY_S` seconds instead.

Bars nest: a bar opened while another is showing does not show itself but counts into the outer
one when both count the same unit, so that long work shows one overall bar (`sandlight.reflectance`
over 216 wavelengths showed 216 bars one after the other, each restarting at 0).

Inside `progress_to(receiver)` nothing is displayed: the outermost bar sends its figures to the
receiver instead (a web job's progress stream), and the receiver may stop the work by raising.
"""

from __future__ import annotations

import contextlib
import contextvars
import sys
import time
from collections.abc import Callable, Iterator

#: Seconds between the plain progress lines written when the output is not a terminal.
PLAIN_EVERY_S = 30.0

_current: contextvars.ContextVar[ProgressBar | _Reported | None] = contextvars.ContextVar(
    "sandlight_progress", default=None
)

#: ``receiver(completed, total, description)``: where the progress goes instead of a display.
ProgressReceiver = Callable[[float, float, str], None]

_receiver: contextvars.ContextVar[ProgressReceiver | None] = contextvars.ContextVar(
    "sandlight_progress_receiver", default=None
)


def _duration(seconds: float) -> str:
    seconds = int(round(seconds))
    return f"{seconds // 3600}:{seconds // 60 % 60:02d}:{seconds % 60:02d}"


class ProgressBar:
    """A progress display of ``total`` units (see the module docstring); made by `progress_bar`."""

    def __init__(self, description: str, total: float, unit: str, completed: float, show_after_s: float) -> None:
        self.description, self.total, self.unit = description, float(total), unit
        self.completed = self._start = float(completed)
        self._show_after_s = show_after_s
        self._began = self._last_line = time.perf_counter()
        self._rich = None  # (rich Progress, task id) once shown on a terminal
        self._terminal = _stderr_console().is_terminal

    def advance(self, n: float = 1, *, description: str | None = None) -> None:
        """Count ``n`` more units done (and optionally change the description)."""
        self.completed += n
        if description is not None:
            self.description = description
        now = time.perf_counter()
        if now - self._began < self._show_after_s:
            return
        if self._terminal:
            self._show_rich()
        elif now - self._last_line >= PLAIN_EVERY_S:
            self._last_line = now
            print(self.line(now), file=sys.stderr, flush=True)

    def rate(self, now: float | None = None) -> float:
        """Units per second since the bar was opened."""
        elapsed = (time.perf_counter() if now is None else now) - self._began
        return (self.completed - self._start) / elapsed if elapsed > 0 else 0.0

    def line(self, now: float | None = None) -> str:
        """The progress as one plain line: percentage, count, rate, elapsed time and ETA."""
        now = time.perf_counter() if now is None else now
        rate = self.rate(now)
        left = (self.total - self.completed) / rate if rate > 0 else float("nan")
        eta = _duration(left) if left == left else "-"
        return (
            f"{self.description}: {100 * self.completed / max(self.total, 1):.0f}% "
            f"({self.completed:,.0f}/{self.total:,.0f} {self.unit}), {_rate_text(rate, self.unit)}, "
            f"{_duration(now - self._began)} elapsed, ETA {eta}"
        )

    def _show_rich(self) -> None:
        if self._rich is None:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            bar = Progress(
                TextColumn("{task.description}", markup=False),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[rate]}", markup=False),
                TimeElapsedColumn(),
                TextColumn("ETA"),
                TimeRemainingColumn(),
                console=_stderr_console(),
                transient=True,
            )
            bar.start()
            self._rich = (bar, bar.add_task(self.description, total=self.total, rate=""))
        bar, task = self._rich
        bar.update(
            task, completed=self.completed, description=self.description, rate=_rate_text(self.rate(), self.unit)
        )

    def _close(self) -> None:
        if self._rich is not None:
            self._rich[0].stop()


class _Reported:
    """The outermost bar inside `progress_to`: sends every advance to the receiver."""

    def __init__(self, description: str, total: float, unit: str, completed: float, receiver: ProgressReceiver) -> None:
        self.description, self.total, self.unit = description, float(total), unit
        self.completed = float(completed)
        self._receiver = receiver

    def advance(self, n: float = 1, *, description: str | None = None) -> None:
        self.completed += n
        if description is not None:
            self.description = description
        self._receiver(self.completed, self.total, self.description)


class _Joined:
    """A bar opened inside another: counts into the outer bar when they share the unit."""

    def __init__(self, outer: ProgressBar | _Reported, unit: str) -> None:
        self._outer = outer if outer.unit == unit else None

    def advance(self, n: float = 1, *, description: str | None = None) -> None:
        if self._outer is not None:
            self._outer.advance(n, description=description)


class _Off:
    def advance(self, n: float = 1, *, description: str | None = None) -> None:
        pass


def _rate_text(rate: float, unit: str) -> str:
    if rate <= 0:
        return f"– {unit}/s"
    if rate >= 100:
        return f"{rate:,.0f} {unit}/s"
    return f"{rate:.3g} {unit}/s" if rate >= 1 else f"{1 / rate:.3g} s per {unit.rstrip('s')}"


def _stderr_console():  # noqa: ANN202 (rich is imported lazily)
    from rich.console import Console

    return Console(stderr=True, markup=False, highlight=False, emoji=False)


@contextlib.contextmanager
def progress_bar(
    description: str,
    total: float,
    *,
    unit: str,
    completed: float = 0,
    enabled: bool = True,
    show_after_s: float = 0.0,
) -> Iterator[ProgressBar | _Reported | _Joined | _Off]:
    """Report the progress of ``total`` units of work (``unit``, plural: "rays", "samples").

    Parameters
    ----------
    description : str
        What is being done (the caller strips what it did not write itself of control characters).
    completed : float
        Units already done (a resumed job).
    enabled : bool
        False: nothing is shown (``advance`` still works).
    show_after_s : float
        Show nothing before this many seconds have passed (short runs stay quiet).

    Yields
    ------
    An object with ``advance(n, description=None)``.
    """
    outer = _current.get()
    if not enabled:
        yield _Off()
        return
    if outer is not None:
        yield _Joined(outer, unit)
        return
    receiver = _receiver.get()
    if receiver is None:
        bar = ProgressBar(description, total, unit, completed, show_after_s)
    else:
        bar = _Reported(description, total, unit, completed, receiver)
    token = _current.set(bar)
    try:
        yield bar
    finally:
        _current.reset(token)
        if isinstance(bar, ProgressBar):
            bar._close()


@contextlib.contextmanager
def progress_to(receiver: ProgressReceiver) -> Iterator[None]:
    """Send the progress of the work inside the block to ``receiver`` instead of displaying it.

    The outermost enabled bar opened in the block calls ``receiver(completed, total,
    description)`` on every advance (bars nested in it count into it as usual); nothing is
    printed. An exception the receiver raises (`sandlight.errors.Cancelled` for a cancelled web
    job) leaves ``advance`` and so stops the work between two batches, with nothing half-done.
    The receiver holds for the current context only (one thread, one asyncio task).
    """
    token = _receiver.set(receiver)
    try:
        yield
    finally:
        _receiver.reset(token)
