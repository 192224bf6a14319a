# SPDX-License-Identifier: MIT
"""Fixtures of the on-target tests (cases in target_cases.py): the images
are linked once per session, each test gets a fresh emulator on them."""
from __future__ import annotations

import pytest

from mcuemu.images import build_host_sets, host_build_dir, link_target
from mcuemu.runner import HostRunner, TargetRunner
from mcuemu.target import Target

from target_cases import every_design


@pytest.fixture(scope="session")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("mcuemu")


@pytest.fixture(scope="session")
def host(workdir):
    ds = every_design("q15") + every_design("float")
    so = build_host_sets(ds, workdir / "host")
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
            _targets[(core, bank_c)] = link_target(core, "-Os", ds, workdir / name, bank_c)
        return TargetRunner(Target(str(_targets[(core, bank_c)]), core))
    return get
