# SPDX-License-Identifier: MIT
"""The binding finds the library of an installed prefix (`cmake --install
build --prefix P` puts it in P/lib), with the Python package installed into
the same prefix, after the prefix moved, through PNEUFRAC_PREFIX and
through pkg-config; and says where it looked when it finds nothing.

The package is installed the way a wheel installs a pure-Python package:
its files copied into P/lib/pythonX.Y/site-packages (pip would need the
network to build the wheel)."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import BUILD, ROOT

PROBE = """
import numpy as np, pneufrac, pathlib
print(pathlib.Path(pneufrac.__file__).resolve().parent)
print(pneufrac.library_path())
d = pneufrac.design("dd", 20000)
print(repr(float(pneufrac.simulate(d, np.ones(100))[-1])))
"""


def probe(site: Path, cwd: Path, **env_extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("PNEUFRAC_LIBRARY", "PNEUFRAC_PREFIX", "PKG_CONFIG_PATH",
                        "PYTHONPATH", "LD_LIBRARY_PATH")}
    env.update(PYTHONPATH=str(site), **env_extra)
    return subprocess.run([sys.executable, "-c", PROBE], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def prefix(tmp_path_factory):
    if shutil.which("cmake") is None or not (BUILD / "cmake_install.cmake").exists():
        pytest.skip("no cmake or no build tree to install")
    top = tmp_path_factory.mktemp("install")
    p = top / "prefix"
    subprocess.run(["cmake", "--install", str(BUILD), "--prefix", str(p)], check=True,
                   capture_output=True, timeout=300)
    site = p / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / \
        "site-packages"
    shutil.copytree(ROOT / "tools" / "python" / "pneufrac", site / "pneufrac",
                    ignore=shutil.ignore_patterns("__pycache__"))
    return top, p, site


def expected_value():
    import numpy as np
    import pneufrac
    return repr(float(pneufrac.simulate(pneufrac.design("dd", 20000), np.ones(100))[-1]))


def test_package_and_library_in_one_prefix_even_moved(prefix):
    top, p, site = prefix
    r = probe(site, top)
    assert r.returncode == 0, r.stderr
    pkg, lib, value = r.stdout.split("\n")[:3]
    assert Path(pkg) == site / "pneufrac"               # the installed copy, not the checkout
    assert Path(lib) == p / "lib" / "libpneufrac.so"
    assert value == expected_value()
    moved = top / "moved"
    p.rename(moved)
    try:
        site2 = moved / site.relative_to(p)
        r = probe(site2, top)
        assert r.returncode == 0, r.stderr
        assert Path(r.stdout.split("\n")[1]) == moved / "lib" / "libpneufrac.so"
    finally:
        moved.rename(p)


@pytest.fixture
def apart(prefix, tmp_path):
    """The package alone, in a folder with no library above it."""
    site = tmp_path / "elsewhere"
    shutil.copytree(prefix[2] / "pneufrac", site / "pneufrac")
    return site


def test_pneufrac_prefix(prefix, apart, tmp_path):
    _, p, _ = prefix
    r = probe(apart, tmp_path, PNEUFRAC_PREFIX=str(p))
    assert r.returncode == 0, r.stderr
    assert Path(r.stdout.split("\n")[1]) == p / "lib" / "libpneufrac.so"


def test_pkg_config(prefix, apart, tmp_path):
    if shutil.which("pkg-config") is None:
        pytest.skip("no pkg-config")
    _, p, _ = prefix
    r = probe(apart, tmp_path, PKG_CONFIG_PATH=str(p / "lib" / "pkgconfig"))
    assert r.returncode == 0, r.stderr
    assert Path(r.stdout.split("\n")[1]).resolve() == (p / "lib" / "libpneufrac.so").resolve()


def test_nothing_found_says_where_it_looked(prefix, apart, tmp_path):
    r = probe(apart, tmp_path)
    if r.returncode == 0:     # a system-wide install answers the linker's search
        pytest.skip(f"a libpneufrac is installed system-wide: {r.stdout.split()[1]}")
    assert "pneufrac.LibraryError" in r.stderr or "LibraryError" in r.stderr
    assert "PNEUFRAC_PREFIX" in r.stderr and "not found" in r.stderr


def test_a_wrong_setting_is_reported_not_passed_over(prefix, tmp_path):
    _, _, site = prefix
    r = probe(site, tmp_path, PNEUFRAC_PREFIX=str(tmp_path / "nowhere"))
    assert r.returncode != 0
    assert str(tmp_path / "nowhere") in r.stderr
