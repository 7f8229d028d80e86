"""sandlight.io: atomic writes and their short temporary names."""

import os

import pytest

from sandlight.io import TEMPORARY_SUFFIX, temporary_sibling, write_atomically


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
