# SPDX-License-Identifier: MIT
"""Lockstep (--clock external) with pymodbus: the p_c sequence equals
`pneufrac simulate` at the instance's internal rate (fs x substeps, the
input held for the substeps, every substeps-th row), bit for bit in float
and in Q15."""

import json
import subprocess

import pytest

from pfd import CLI, Regs, f32, simulate_exchanges

FS = 1000
DURATION = 0.3  # 301 samples


def run_exchanges(r, inputs):
    """Write e, tick once, read p_c: one exchange per input."""
    pc, pcq = [], []
    for e in inputs:
        r.write("e", e)
        r.tick(1)
        pc.append(r.read("pc"))
        pcq.append(r.read("pc_i16"))
    return pc, pcq


def assert_matches(pc, pcq, ref, arith):
    """Bit for bit: Q15 the raw output, float the binary32 value."""
    assert len(pc) == len(ref)
    if arith == "q15":
        assert pcq == [int(row["pc_q15"]) for row in ref]
    else:
        assert pc == [f32(row["pc"]) for row in ref]


def assert_matches_simulate(r, ref, arith):
    """A unit step through len(ref) exchanges."""
    pc, pcq = run_exchanges(r, [1.0] * len(ref))
    assert_matches(pc, pcq, ref, arith)


@pytest.mark.parametrize("arith", ["float", "q15"])
def test_default_example6_matches_simulate(daemon, arith):
    """The defaults: 1 kHz exchanges, 20 substeps (the relay's tau = 1 ms
    asks for 20 kHz inside)."""
    d = daemon("--clock", "external", "--arith", arith)
    r = Regs(d.client())
    assert r.read("committed_substeps") == 0
    k = r.read("substeps_used")
    assert k == 20 and r.read("internal_fs") == 20000.0
    assert r.read("step_cost_ns") > 0
    extra = ["--arith", "q15", "--in-fs", "1", "--out-fs", "0.01"] if arith == "q15" else ["--arith", "float"]
    ref = simulate_exchanges(FS, k, "--config", "dd", "--duration", str(DURATION), *extra)
    assert_matches_simulate(r, ref, arith)
    assert r.read("samples") == len(ref)


@pytest.mark.parametrize("arith", ["float", "q15"])
@pytest.mark.parametrize("fs,substeps", [(1500.0, 7), (200.0, 1), (100.0, 0)])
def test_substeps_with_a_changing_input(daemon, tmp_path, arith, fs, substeps):
    """A committed exchange rate and substeps (0: the rule's, 200 at
    100 Hz), and an input that changes at every exchange, held in
    between."""
    d = daemon("--clock", "external")
    r = Regs(d.client())
    resp = r.write_many([("arith", 1 if arith == "q15" else 0), ("fs", fs)])
    assert not resp.isError(), resp
    r.write("substeps", substeps)
    r.write("commit", 1)
    r.tick(1)  # switched in at rest
    k = r.read("substeps_used")
    assert r.read("committed_substeps") == substeps
    assert k == (substeps or 200)
    assert r.read("internal_fs") == fs * k
    inputs = [f32(0.8 if n % 9 < 4 else -0.3 + 0.01 * n) for n in range(120)]
    extra = (["--arith", "q15", "--in-fs", "1", "--out-fs", "0.01"]
             if arith == "q15" else ["--arith", "float"])
    ref = simulate_exchanges(fs, k, "--config", "dd", "--duration", repr((len(inputs) - 1) / fs),
                             *extra, inputs=inputs, tmp_path=tmp_path)
    pc, pcq = run_exchanges(r, inputs)
    assert_matches(pc, pcq, ref, arith)


def paper_defaults(config):
    out = subprocess.run([CLI, "design", "--config", config, "--fs", "1000", "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["params"]


@pytest.mark.parametrize("config,arith,out_fs", [
    ("p", "float", 0.01), ("id", "float", 16.0), ("pid", "float", 16.0),
    ("p", "q15", 0.01), ("id", "q15", 16.0), ("pid", "q15", 16.0)])
def test_committed_configuration_matches_simulate(daemon, config, arith, out_fs):
    """The whole set arrives over Modbus: staged registers, then commit."""
    d = daemon("--clock", "external")
    r = Regs(d.client())
    cfg = {"p": 0, "dd": 1, "id": 2, "pid": 3}[config]
    resp = r.write_many([("config", cfg), ("arith", 1 if arith == "q15" else 0),
                         ("fs", 2000.0), ("in_fs", 1.0), ("out_fs", out_fs)])
    assert not resp.isError(), resp
    # The paper's parameters go over the wire as float32: give simulate the
    # same (rounded) values.
    sets = []
    for name, value in paper_defaults(config).items():
        as_f32 = f32(value)
        r.write(name, as_f32)
        sets += ["--set", f"{name}={as_f32!r}"]
    r.write("commit", 1)
    assert r.read("committed_config") == cfg
    r.tick(1)  # switched in at this sample, still at rest (e = 0)
    extra = (["--arith", "q15", "--in-fs", "1", "--out-fs", repr(out_fs)]
             if arith == "q15" else ["--arith", "float"])
    ref = simulate_exchanges(2000, r.read("substeps_used"), "--config", config,
                             "--duration", "0.15", *sets, *extra)
    assert_matches_simulate(r, ref, arith)


@pytest.mark.parametrize("arith", ["float", "q15"])
def test_refused_commit_keeps_the_pending_one(daemon, arith):
    """Commit A, then a refused commit B before the loop has taken A (no
    tick between): A must still be switched in at the next sample, as
    `committed_*` and the config file say."""
    d = daemon("--clock", "external")
    r = Regs(d.client())
    resp = r.write_many([("config", 3), ("arith", 1 if arith == "q15" else 0),
                         ("fs", 2000.0), ("in_fs", 1.0), ("out_fs", 16.0)])
    assert not resp.isError(), resp
    sets = []
    for name, value in paper_defaults("pid").items():
        as_f32 = f32(value)
        r.write(name, as_f32)
        sets += ["--set", f"{name}={as_f32!r}"]
    r.write("commit", 1)  # A: pending until the next tick
    assert r.read("status") & (1 << 8)
    # B: each value in range, the set is not (pmin > pmax).
    assert not r.write_many([("pmin", 50.0), ("pmax", 2.0)]).isError()
    resp = r.write_raw("commit", 1)
    assert resp.isError() and resp.exception_code == 3, resp
    assert r.read("commit_result") == 1
    assert r.read("committed_config") == 3
    r.tick(1)  # A switched in here, at rest
    assert not r.read("status") & (1 << 8)
    extra = (["--arith", "q15", "--in-fs", "1", "--out-fs", "16.0"]
             if arith == "q15" else ["--arith", "float"])
    ref = simulate_exchanges(2000, r.read("substeps_used"), "--config", "pid",
                             "--duration", "0.15", *sets, *extra)
    assert_matches_simulate(r, ref, arith)


def test_replaced_pending_commit_clears_bit8(daemon):
    """Two commits without a sample between: the second replaces the first
    before the loop takes it. Status bit 8 (commit not yet switched in)
    must clear once the loop runs the second, and `commits` counts both."""
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("e", 1.0)
    r.tick(10)
    r.write("k2", 0.2)
    r.write("commit", 1)
    r.write("k2", 0.3)
    r.write("commit", 1)
    assert r.read("status") & (1 << 8)
    assert r.read("commits") == 2
    r.tick(1)
    assert not r.read("status") & (1 << 8)
    r.tick(100)
    assert not r.read("status") & (1 << 8)
    assert r.read("committed_k2") == f32(0.3)
