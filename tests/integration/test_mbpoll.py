# SPDX-License-Identifier: MIT
"""The README's mbpoll and pymodbus examples, run exactly as written
(only the port is the test's free one instead of 1502), against the real
daemon; their effects are checked with pymodbus."""

import re
import shlex
import subprocess
import sys

import pytest

from pfd import ROOT, Regs

README = (ROOT / "README.md").read_text()


def block(heading, lang):
    part = README.split(heading, 1)[1]
    return re.search(r"```" + lang + r"\n(.*?)```", part, re.S).group(1)


MBPOLL = [line.split("#", 1)[0].strip() for line in block("### mbpoll", "sh").splitlines()
          if line.startswith("mbpoll ")]
PYMODBUS = block("### pymodbus", "python")


def run_mbpoll(cmd, port):
    assert " -p 1502 " in cmd
    argv = shlex.split(cmd.replace(" -p 1502 ", f" -p {port} "))
    return subprocess.run(argv, capture_output=True, text=True, timeout=30)


def values(out):
    """mbpoll's '[ref]: value' lines."""
    return {int(m.group(1)): m.group(2) for m in re.finditer(r"^\[(\d+)\]:\s+(\S+)", out, re.M)}


def test_readme_has_the_examples():
    assert len(MBPOLL) == 5
    assert "ModbusTcpClient" in PYMODBUS


def test_mbpoll_examples_as_written(daemon):
    d = daemon()
    r = Regs(d.client())
    write_e, read_out, read_q, read_status, bad_mode = MBPOLL

    p = run_mbpoll(write_e, d.port)
    assert p.returncode == 0, p.stdout + p.stderr
    assert r.read("e") == 0.5

    p = run_mbpoll(read_out, d.port)
    assert p.returncode == 0, p.stdout + p.stderr
    v = values(p.stdout)
    assert sorted(v) == [0, 2, 4, 6]
    pc_mbpoll = float(v[0])
    pc_now = r.read("pc")
    # The loop runs on between the two reads; p_c of a 0.5 step settles
    # near 0.0045 and only grows.
    assert 0 < pc_mbpoll <= pc_now * 1.0001 and pc_now < 0.005
    assert float(v[2]) == pytest.approx(r.read("x"), rel=0.05)

    p = run_mbpoll(read_q, d.port)
    assert p.returncode == 0, p.stdout + p.stderr
    assert float(values(p.stdout)[66]) == pytest.approx(r.read("committed_q"), rel=1e-6)

    p = run_mbpoll(read_status, d.port)
    assert p.returncode == 0, p.stdout + p.stderr
    v = values(p.stdout)
    assert int(v[15]) & 1  # running
    assert int(v[16]) == 0  # last commit ok
    assert int(v[19]) == 0  # no commit

    p = run_mbpoll(bad_mode, d.port)
    assert p.returncode != 0
    assert "Illegal data value" in p.stdout + p.stderr
    assert r.read("mode") == 0


def test_pymodbus_example_as_written(daemon, tmp_path):
    d = daemon()
    script = tmp_path / "example.py"
    assert 'port=1502' in PYMODBUS
    script.write_text(PYMODBUS.replace("port=1502", f"port={d.port}"))
    p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    m = re.match(r"p_c = (\S+)  x = (\S+)  p_b = (\S+)  y = (\S+)", p.stdout)
    assert m, p.stdout
    r = Regs(d.client())
    assert r.read("e") == 0.5
    assert r.read("committed_q") == pytest.approx(0.8, rel=1e-7)
    # p_c of a 0.5 step, switched bumplessly from q = 0.9 to 0.8 (the
    # output blends the two sets' responses): positive, and within the
    # default out_fs, 0.01, which Example 6's response never leaves.
    assert 0 < float(m.group(1)) < 0.01
