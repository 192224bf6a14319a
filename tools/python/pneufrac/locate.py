# SPDX-License-Identifier: MIT
"""Where libpneufrac.so is: the places the binding tries, in order.

- ``PNEUFRAC_LIBRARY``: the shared object itself;
- ``PNEUFRAC_PREFIX``: an installation prefix (``cmake --install build
  --prefix PREFIX`` puts the library in PREFIX/lib).

Either variable, when set, is the only place tried: a wrong setting is
reported, not passed over for another library. Without them:

- beside this package: in each folder above it, a build tree
  (``build/lib``: a checkout with an editable install) or an installation
  prefix (``lib``, ``lib64``, ``lib/<multiarch>``: the C library and the
  Python package installed into the same prefix, a venv or /usr/local);
- ``pkg-config --variable=libdir pneufrac`` (the installed pneufrac.pc
  knows its own prefix, even after the prefix was moved);
- the dynamic linker's own search (``ctypes.util.find_library``).
"""
from __future__ import annotations

import ctypes.util
import os
import subprocess
import sys
from pathlib import Path

NAME = "libpneufrac.so"
# Library folders of a prefix, as GNUInstallDirs names them on Linux.
LIBDIRS = ("lib", "lib64")


def _multiarch() -> list[str]:
    arch = getattr(sys.implementation, "_multiarch", "")
    return [f"lib/{arch}"] if arch else []


def in_prefix(prefix: Path) -> list[Path]:
    """The library paths of an installation prefix."""
    return [prefix / d / NAME for d in (*LIBDIRS, *_multiarch())]


def _beside_package() -> list[Path]:
    here = Path(__file__).resolve().parent
    out = []
    for up in here.parents:
        out.append(up / "build" / "lib" / NAME)
        out += in_prefix(up)
    return out


def _pkg_config() -> list[Path]:
    try:
        r = subprocess.run(["pkg-config", "--variable=libdir", "pneufrac"],
                           capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return []
    libdir = r.stdout.strip()
    return [Path(libdir) / NAME] if r.returncode == 0 and libdir else []


def searched() -> str:
    """The places candidates() looks without the environment variables, in
    words: what a "not found" message names when none of them held it."""
    here = Path(__file__).resolve().parent
    dirs = ", ".join(("build/lib", *LIBDIRS, *_multiarch()))
    return (f"the folders {dirs} of every folder above {here}; pkg-config's "
            "pneufrac; the dynamic linker's path")


def candidates():
    """Paths to try, best first. Searched paths that do not exist are
    skipped; the environment's are yielded as they are, alone."""
    env = os.environ.get("PNEUFRAC_LIBRARY")
    if env:
        yield Path(env)
        return
    prefix = os.environ.get("PNEUFRAC_PREFIX")
    if prefix:
        found = [p for p in in_prefix(Path(prefix)) if p.exists()]
        yield from found or [Path(prefix) / "lib" / NAME]
        return
    for p in _beside_package():
        if p.exists():
            yield p
    for p in _pkg_config():
        if p.exists():
            yield p
    name = ctypes.util.find_library("pneufrac")
    if name:
        yield Path(name)
