# SPDX-License-Identifier: MIT
"""Fixtures of the on-target tests (cases in target_cases.py): the images
are linked once per run, each test gets a fresh emulator on them.

scripts/test.sh runs these tests on one pytest-xdist worker per core. The
images are then built once for all workers: in a folder they share, each
under its own lock, by the first worker that needs it; the others wait
for it and load the same files."""
from __future__ import annotations

import os

import pytest

from mcuemu.images import build_host_sets, built_once, host_build_dir, link_target
from mcuemu.runner import HostRunner, TargetRunner
from mcuemu.target import Target

from target_cases import every_design


@pytest.fixture(scope="session")
def workdir(tmp_path_factory):
    """The run's image folder: under pytest-xdist the parent of the
    workers' own temporary folders (one per run, shared by its workers),
    else the session's."""
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent
    d = base / "mcuemu"
    d.mkdir(exist_ok=True)
    return d


@pytest.fixture(scope="session")
def host(workdir):
    ds = every_design("q15") + every_design("float")
    so = built_once(workdir / "host", lambda out: build_host_sets(ds, out))
    return HostRunner(host_build_dir() / "lib" / "libpneufrac.so", so)


_targets: dict = {}


@pytest.fixture(scope="session")
def target_of(workdir):
    """target_of(core, bank_c=False) -> TargetRunner on a fresh image at
    -Os (built once); bank_c: the M0+ build with the bank's C loop instead
    of its assembly one."""
    def get(core: str, bank_c: bool = False) -> TargetRunner:
        if (core, bank_c) not in _targets:
            ds = every_design("q15") + (every_design("float") if core == "m4" else [])
            name = core + ("-c" if bank_c else "")
            _targets[(core, bank_c)] = built_once(
                workdir / name, lambda out: link_target(core, "-Os", ds, out, bank_c))
        return TargetRunner(Target(str(_targets[(core, bank_c)]), core))
    return get
