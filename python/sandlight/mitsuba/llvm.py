"""Finding the LLVM library Dr.Jit's llvm variants need (``DRJIT_LIBLLVM_PATH``).

Public objects
--------------
find_libllvm
    The path of a usable libLLVM (version ≥ 16; Debian's ``libllvm19`` package), or None.
configure_llvm
    Point ``DRJIT_LIBLLVM_PATH`` at it unless the variable is already set (call before
    ``import mitsuba``).

Dr.Jit searches the default library path for ``libLLVM.so``; on Debian 12 that finds LLVM 14 or
15, which it refuses or which crash it. ``apt-get install libllvm19`` installs
``/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`` (and ``libLLVM-19.so``).
"""

from __future__ import annotations

import glob
import os
import re

__all__ = ["find_libllvm", "configure_llvm", "MIN_LLVM_MAJOR"]

#: Oldest LLVM major version used (Dr.Jit 1.x refuses or crashes with 14 and 15 here).
MIN_LLVM_MAJOR = 16
_SEARCH = ("/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib", "/usr/local/lib")
_VERSIONED = re.compile(r"libLLVM(?:\.so\.|-)(\d+)")


def find_libllvm() -> str | None:
    """The newest libLLVM of major version ≥ `MIN_LLVM_MAJOR` in the system library folders."""
    found = []
    for folder in _SEARCH:
        for path in glob.glob(os.path.join(folder, "libLLVM*.so*")):
            m = _VERSIONED.search(os.path.basename(path))
            if m and int(m.group(1)) >= MIN_LLVM_MAJOR and os.path.isfile(path):
                found.append((int(m.group(1)), path))
    return max(found)[1] if found else None


def configure_llvm() -> str | None:
    """Set ``DRJIT_LIBLLVM_PATH`` to `find_libllvm` if it is unset; returns the value in force."""
    if not os.environ.get("DRJIT_LIBLLVM_PATH"):
        path = find_libllvm()
        if path is not None:
            os.environ["DRJIT_LIBLLVM_PATH"] = path
    return os.environ.get("DRJIT_LIBLLVM_PATH")
