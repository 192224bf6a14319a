# SPDX-License-Identifier: MIT
"""One version everywhere (the three lines of pneufrac.h), and every
program's --help says what its exit statuses mean."""
import importlib.metadata
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import CLI, ROOT

BIN = Path(sys.executable).parent
DAEMON = os.environ.get("PNEUFRACD", str(ROOT / "build/port/posix/pneufracd"))
FIT = str(BIN / "pneufrac-fit")
REDUCE = str(BIN / "pneufrac-reduce")
PLOT = os.environ.get("PNEUFRAC_PLOT", str(BIN / "pneufrac-plot"))


def header_version():
    text = (ROOT / "lib/include/pneufrac/pneufrac.h").read_text()
    parts = [re.search(rf"#define PNEUFRAC_VERSION_{p} +(\d+)", text).group(1)
             for p in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


def out(*cmd):
    r = subprocess.run(list(cmd), capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, (cmd, r.stderr)
    return r.stdout


def test_every_program_has_the_header_version():
    v = header_version()
    import pneufrac
    import pneufrac_fit
    assert out(CLI, "--version") == f"pneufrac {v}\n"
    assert re.fullmatch(rf"pneufracd {re.escape(v)} \(register map \d+\)\n",
                        out(DAEMON, "--version"))
    assert out(FIT, "--version") == f"pneufrac-fit {v}\n"
    assert out(REDUCE, "--version") == f"pneufrac-reduce {v}\n"
    assert pneufrac.__version__ == pneufrac_fit.__version__ == v
    assert importlib.metadata.version("pneufrac") == v


def test_cmake_package_version_file_has_it_too():
    cfg = ROOT / "build/pneufracConfigVersion.cmake"
    if not cfg.exists():
        pytest.skip("no build/pneufracConfigVersion.cmake (not the top-level build)")
    assert f'set(PACKAGE_VERSION "{header_version()}")' in cfg.read_text()


HELPS = [
    [CLI, "--help"],
    *([CLI, c, "--help"] for c in ("simulate", "step", "bode", "design", "demo", "reproduce")),
    [DAEMON, "--help"],
    [FIT, "--help"],
    [FIT, "diagnose", "--help"],
    [FIT, "generate", "--help"],
    [PLOT, "--help"],
    [REDUCE, "--help"],
]


@pytest.mark.parametrize("cmd", HELPS, ids=[" ".join(Path(c[0]).name for c in [h]) + " "
                                             + " ".join(h[1:]) for h in HELPS])
def test_help_lists_the_exit_statuses(cmd):
    text = " ".join(out(*cmd).split())
    m = re.search(r"Exit status: (.*)", text)
    assert m, f"{cmd}: no 'Exit status:' in --help"
    # 0 and the usage error (2) at least, each with what it means
    assert re.search(r"\b0 \w", m.group(1)) and re.search(r"\b2 \w", m.group(1))
