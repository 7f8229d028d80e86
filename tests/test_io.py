"""sandlight.io: atomic writes, short temporary names, cleanup of a killed writer's leftovers."""

import os
import subprocess
import sys

import pytest

from sandlight.io import TEMPORARY_SUFFIX, is_stale_temporary, temporary_sibling, write_atomically


def _dead_pid() -> int:
    """The id of a process that has exited (and been reaped)."""
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, check=True)
    return int(proc.stdout)


def _write_text(text):
    return lambda tmp: tmp.write_text(text, encoding="utf-8")


@pytest.mark.parametrize("name", ["r" * 251 + ".csv", "é" * 126 + ".nc"])
def test_a_name_at_the_length_limit_can_be_written(tmp_path, name):
    # 255 bytes is the limit of one file name; the temporary name must not add to it (issue 24 #3).
    assert len(os.fsencode(name)) == 255
    target = write_atomically(tmp_path / name, _write_text("x"))
    assert target.read_text() == "x" and os.listdir(tmp_path) == [name]
    assert len(os.fsencode(temporary_sibling(tmp_path / name).name)) < 110


def test_a_temporary_name_keeps_the_start_of_the_name_and_the_process_id(tmp_path):
    tmp = temporary_sibling(tmp_path / "spectrum.nc")
    assert tmp.parent == tmp_path and tmp.name.startswith(f".spectrum.nc.{os.getpid()}.")
    assert tmp.name.endswith(TEMPORARY_SUFFIX) and tmp != temporary_sibling(tmp_path / "spectrum.nc")


def test_the_next_write_removes_the_leftovers_of_a_killed_writer(tmp_path):
    target = tmp_path / "out.nc"
    dead = tmp_path / f".out.nc.{_dead_pid()}.0123456789ab.part"
    live = temporary_sibling(target)  # this process is writing it right now
    other = tmp_path / f".other.nc.{_dead_pid()}.0123456789ab.part"  # another target's: not this write's
    mine = tmp_path / "notes.part"  # not a temporary name: never touched
    for p in (dead, live, other, mine):
        p.write_bytes(b"half a file")
    assert is_stale_temporary(dead) and not is_stale_temporary(live) and not is_stale_temporary(mine)
    write_atomically(target, _write_text("done"))
    assert not dead.exists() and live.exists() and other.exists() and mine.exists()
    assert target.read_text() == "done"


def test_a_leftover_older_than_the_process_now_holding_its_id_is_stale(tmp_path):
    # Process ids are reused: a temporary last written before its "owner" started is not its.
    leftover = tmp_path / f".out.nc.{os.getpid()}.0123456789ab.part"
    leftover.write_bytes(b"half a file")
    assert not is_stale_temporary(leftover)
    before_start = _own_start_time() - 3600
    os.utime(leftover, (before_start, before_start))
    assert is_stale_temporary(leftover)
    write_atomically(tmp_path / "out.nc", _write_text("done"))
    assert not leftover.exists()


def _own_start_time() -> float:
    import psutil

    return psutil.Process().create_time()
