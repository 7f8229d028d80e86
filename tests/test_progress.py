"""One progress display (issue 24): nested bars count into the outer one, plain lines off a terminal."""

import re

import pytest

import sandlight
from sandlight import _runner, engine, progress
from sandlight.errors import Cancelled
from sandlight.progress import progress_bar


def test_nested_bars_of_one_unit_count_into_the_outer_bar(monkeypatch, capsys):
    monkeypatch.setattr(progress, "PLAIN_EVERY_S", 0.0)  # pytest's stderr is not a terminal: plain lines
    with progress_bar("outer", 10, unit="rays") as outer:
        for i in range(2):
            with progress_bar(f"inner {i}", 5, unit="rays") as inner:
                inner.advance(5, description=f"λ {i}")
            with progress_bar("other unit", 3, unit="rows") as other:
                other.advance(3)  # not rays: counted nowhere
    assert outer.completed == 10
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 2 and lines[-1].startswith("λ 1: 100% (10/10 rays), ")
    assert "elapsed, ETA 0:00:00" in lines[-1]


def test_a_spectrum_shows_one_bar_over_all_its_wavelengths(monkeypatch, capsys):
    # one bar per wavelength, each restarting at 0, was shown 216 times for 350:2500:10
    monkeypatch.setattr(progress, "PLAIN_EVERY_S", 0.0)
    monkeypatch.setattr(engine, "SHOW_AFTER_SECONDS", 0.0)
    monkeypatch.setattr(_runner, "SHOW_AFTER_SECONDS", 0.0)
    sandlight.reflectance("red-dune", [450, 550, 650], rays=3000, share=False)
    lines = capsys.readouterr().err.splitlines()
    assert lines and all("/9,000 rays)" in line for line in lines), lines
    assert lines[-1].startswith("λ = 650 nm (3/3): 100% (9,000/9,000 rays)")
    # with shared paths, one bar over all the groups
    sandlight.reflectance("red-dune", [450, 550, 650], rays=3000, share=True)
    lines = capsys.readouterr().err.splitlines()
    totals = {re.search(r"/([\d,]+) rays\)", line).group(1) for line in lines}
    assert len(totals) == 1 and ": 100% (" in lines[-1], lines


def test_disabled_bars_print_nothing(monkeypatch, capsys):
    monkeypatch.setattr(progress, "PLAIN_EVERY_S", 0.0)
    with progress_bar("quiet", 4, unit="rays", enabled=False) as bar:
        bar.advance(4)
    assert capsys.readouterr().err == ""


def test_progress_to_sends_the_outer_bar_to_the_receiver_and_prints_nothing(capsys):
    seen = []
    with progress.progress_to(lambda done, total, text: seen.append((done, total, text))):
        sandlight.reflectance("red-dune", [450, 550, 650], rays=3000, share=False)
    assert seen and seen[-1][:2] == (9000.0, 9000.0)
    assert [s[0] for s in seen] == sorted(s[0] for s in seen)
    assert capsys.readouterr().err == ""


def test_a_receiver_that_raises_stops_the_run_within_a_batch():
    calls = []

    def cancel(done, total, text):
        calls.append(done)
        raise sandlight.errors.Cancelled("stopped by the test")

    with pytest.raises(Cancelled), progress.progress_to(cancel):
        sandlight.reflectance("red-dune", [450, 550, 650], rays=200000, share=False)
    assert len(calls) == 1 and calls[0] < 200000
