# SPDX-License-Identifier: MIT
"""docs/python.md's tour runs as written: its shell block, then its Python
blocks in order, in one interpreter, from a folder that has the
repository's .venv (as the repository's root has)."""
import os
import re
import subprocess
import sys
from pathlib import Path

from conftest import ROOT

DOC = ROOT / "docs" / "python.md"


def blocks(text: str, lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", text, re.S)


def test_the_tour_runs_as_written(tmp_path):
    tour = DOC.read_text().split("## A tour", 1)[1]
    shell = blocks(tour, "sh")
    python = blocks(tour, "python")
    assert len(shell) == 1 and len(python) >= 6
    venv = Path(sys.executable).parent.parent
    (tmp_path / ".venv").symlink_to(venv)
    env = dict(os.environ, MPLBACKEND="Agg")
    subprocess.run(["bash", "-euo", "pipefail", "-c", shell[0]], cwd=tmp_path, env=env,
                   check=True, timeout=300)
    script = tmp_path / "tour.py"
    script.write_text("\n".join(python))
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "dead_time" in r.stdout                   # the diagnosis named the cause
    assert (tmp_path / "dd-bode.png").stat().st_size > 1000
