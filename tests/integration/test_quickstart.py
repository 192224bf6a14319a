# SPDX-License-Identifier: MIT
"""The README's first command drives pneufracd with
port/posix/examples/step_client.py (scripts/demo.sh). Run that client, as
the demo does, against a lockstep daemon: what it prints and writes must
be Example 6's step response as `pneufrac simulate` computes it, so the
quick start cannot rot without a red test. (demo.sh itself also runs
scripts/setup.sh, which rebuilds build/: not something to do under a
running ctest.)"""

import csv
import subprocess
import sys

from pfd import ROOT, f32, simulate_exchanges

CLIENT = ROOT / "port/posix/examples/step_client.py"
SAMPLES = 300


def test_step_client_shows_example6s_response(daemon, tmp_path):
    d = daemon("--clock", "external")
    out_csv = tmp_path / "step.csv"
    run = subprocess.run([sys.executable, str(CLIENT), "--port", str(d.port),
                          "--samples", str(SAMPLES), "--csv", str(out_csv)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert f"{SAMPLES} samples; peak p_c" in run.stdout
    with open(out_csv) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == SAMPLES
    assert all(float(r["e"]) == 1.0 for r in rows)
    # The daemon's default: Example 6 in float, 1 kHz exchanges, 20 substeps.
    ref = simulate_exchanges(1000, 20, "--config", "dd", "--arith", "float",
                             "--duration", repr((SAMPLES - 1) / 1000))
    # The client writes 9 significant digits, which name one binary32
    # value: bit for bit, as test_lockstep asserts through pymodbus.
    got = [f32(r["pc"]) for r in rows]
    want = [f32(r["pc"]) for r in ref]
    assert got == want
