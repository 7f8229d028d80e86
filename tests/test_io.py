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


def test_read_regular_file_reads_a_file_and_refuses_the_rest(tmp_path):
    from sandlight.errors import ParameterError
    from sandlight.io import read_regular_file

    (tmp_path / "s.toml").write_bytes(b"a = 1\n")
    (tmp_path / "link.toml").symlink_to(tmp_path / "s.toml")
    assert read_regular_file(tmp_path / "link.toml", "sample file", max_bytes=6) == b"a = 1\n"
    with pytest.raises(ParameterError, match="at most 5 bytes"):
        read_regular_file(tmp_path / "s.toml", "sample file", max_bytes=5)
    os.mkfifo(tmp_path / "fifo")  # opening it blocking would wait for a writer
    (tmp_path / "zero").symlink_to("/dev/zero")
    for special in (tmp_path, tmp_path / "fifo", tmp_path / "zero"):
        with pytest.raises(ParameterError, match="a regular file"):
            read_regular_file(special, "sample file", max_bytes=100)
    with pytest.raises(FileNotFoundError):
        read_regular_file(tmp_path / "missing", "sample file", max_bytes=100)
