# SPDX-License-Identifier: MIT
"""The programs under test, from the environment ctest sets
(tests/CMakeLists.txt), or the default build tree."""
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PNEUFRAC_CLI", str(ROOT / "build/tools/pneufrac"))


def run(*args, check=True, **kw):
    """`pneufrac ARGS` with text output."""
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True,
                          timeout=300, check=check, **kw)


@pytest.fixture
def cli():
    return run
