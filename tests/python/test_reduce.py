# SPDX-License-Identifier: MIT
"""pneufrac-reduce (tools/python/pneufrac_reduce) and the bank runtimes
(lib pf_bank_*, host build):
  - the reduced bank's step response is within the requested tolerance of
    the full design's, measured against `pneufrac simulate` (the C CLI's
    own run, not the tool's), for every configuration, with a lag;
  - every normalised state is bounded by 0.98 of the input's full scale,
    and reaches that bound's worst case only under the worst input;
  - the Q15 runtime is within 1 LSB of the same bank in double and the
    float runtime within 1e-5 of its peak, real sections and complex pairs;
  - a dead time delays the output by exactly its samples;
  - in-loop effects, integrating designs and bad arguments are refused
    with one line and the documented exit status.
"""
from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from mcuemu.images import Design, build_host_sets, build_host_table, write_table
from mcuemu.runner import HostRunner

from pneufrac_reduce import cli, export, fixed
from pneufrac_reduce.realise import Bank, realise

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "build" / "tools" / "pneufrac"
LIB = ROOT / "build" / "lib" / "libpneufrac.so"
CONFIGS = ("p", "dd", "id", "pid")
# Q15 output full scales that keep each configuration's response inside
# Q15 for most of a full-scale stimulus (as tests/target).
OUT_FS = {"p": 0.02, "dd": 0.02, "id": 20.0, "pid": 20.0}
FS = 20000.0


def reduce_cli(*args, check=True):
    r = subprocess.run([sys.executable, "-m", "pneufrac_reduce", *map(str, args)],
                       capture_output=True, text=True, cwd=ROOT)
    if check and r.returncode != 0:
        raise AssertionError(f"pneufrac-reduce {' '.join(map(str, args))}: {r.stderr}")
    return r


def bank_of(rec: dict) -> Bank:
    b = rec["bank"]
    return Bank(fs=rec["fs"], d=b["d"], lam=np.array(b["lam"]), beta=np.array(b["beta"]),
                alpha=np.array(b["alpha"]), omega=np.array(b["omega"]),
                beta_pair=np.array(b["beta_pair"]).reshape(-1, 2), delay_len=b["delay_len"])


def simulate(config, seconds, *extra):
    """The full design's unit-step response from the C CLI."""
    r = subprocess.run([str(CLI), "simulate", "--config", config, "--fs", str(FS),
                        "--duration", str(seconds), *extra], capture_output=True, text=True,
                       check=True)
    return np.loadtxt(io.StringIO(r.stdout), delimiter=",", skiprows=1, comments="#")[:, 2]


def stimulus(n: int, seed: int) -> np.ndarray:
    """Full-scale steps both ways, holds, ramps, sines up to near Nyquist,
    noise and alternation (the worst input of a section near z = -1)."""
    rng = np.random.default_rng(seed)
    parts, total = [], 0
    while total < n:
        m, kind = int(rng.integers(20, 4000)), int(rng.integers(0, 6))
        t, amp = np.arange(m), rng.uniform(-1, 1)
        parts.append([np.full(m, amp), np.full(m, rng.choice([-1.0, 1.0])),
                      np.linspace(rng.uniform(-1, 1), amp, m),
                      amp * np.sin(2 * np.pi * rng.uniform(1e-4, 0.45) * t),
                      np.clip(amp + 0.1 * rng.standard_normal(m), -1, 1),
                      np.where(t % 2 == 0, 1.0, -1.0)][kind])
        total += m
    return np.concatenate(parts)[:n]


@pytest.fixture(scope="module")
def records():
    """JSON records of every configuration at the defaults, and a dd with
    an output lag."""
    out = {c: json.loads(reduce_cli("--config", c, "--fs", FS, "--format", "json").stdout)
           for c in CONFIGS}
    out["dd-lag"] = json.loads(reduce_cli("--config", "dd", "--fs", FS, "--format", "json",
                                          "--effect", "lag:tau=0.002").stdout)
    return out


@pytest.mark.parametrize("case", list(CONFIGS) + ["dd-lag"])
def test_step_within_tolerance_of_the_full_design(records, case):
    rec = records[case]
    config, extra = (case, ()) if case in CONFIGS else ("dd", ("--effect", "lag:tau=0.002"))
    t0, t1 = rec["horizon"]
    full = simulate(config, t1, *extra)
    n = np.arange(len(full))
    err = np.abs(bank_of(rec).step(n) - full)
    window = n >= round(t0 * FS)
    worst = err[window].max() / np.abs(full[window]).max()
    assert worst <= rec["tol"], f"{case}: {worst:.3g} > {rec['tol']}"
    # the record says what was measured (within rounding of the two runs)
    assert worst == pytest.approx(rec["error"], rel=1e-3, abs=1e-9)
    assert rec["order"] < rec["full_order"] / 3


def test_a_tighter_tolerance_needs_no_fewer_states(records):
    tight = json.loads(reduce_cli("--config", "dd", "--fs", FS, "--format", "json",
                                  "--tol", "1e-4").stdout)
    assert tight["order"] >= records["dd"]["order"] and tight["error"] <= 1e-4


@pytest.mark.parametrize("config", CONFIGS)
def test_states_bounded_for_any_input(records, config):
    bank = bank_of(records[config])
    gain = 1.0 / OUT_FS[config]
    s = fixed.scale(bank, gain)
    l1 = bank.lam / (1.0 - np.abs(1.0 - bank.lam))
    bound = np.abs(s.beta) * l1
    assert np.all(bound <= fixed.STATE_BOUND) and np.all(bound > fixed.STATE_BOUND / 2)
    # The bound is reached: the worst input of each section (the sign of its
    # impulse response, reversed) drives it to the bound, no further.
    for lam, beta, b in zip(bank.lam, s.beta, bound):
        n = min(int(40 / lam), 400_000)
        h = lam * (1.0 - lam) ** np.arange(n)
        worst = abs(beta * np.sum(np.abs(h)))
        assert worst <= b * (1 + 1e-9) and worst >= b * (1 - 1e-9) * (1 - abs(1 - lam) ** n)


def _hosts(designs, tmp):
    return HostRunner(LIB, build_host_sets(designs, tmp))


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    ds = [Design(f"r_{c}_q15", c, "q15", out_fs=OUT_FS[c], kind="bank") for c in CONFIGS]
    ds += [Design(f"r_{c}_f32", c, "float", kind="bank") for c in CONFIGS]
    return _hosts(ds, tmp_path_factory.mktemp("banks"))


def q15_vs_double(runner, index, bank, in_fs, out_fs, u):
    uq = np.clip(np.round(u * 32768), -32768, 32767).astype(np.int16)
    got = runner.run(runner.new("q15", index, "bank"), uq).astype(float)
    want = bank.run(uq / 32768.0 * in_fs) / out_fs * 32768.0
    inside = np.abs(want) < 32767.0
    assert inside.mean() > 0.5
    return np.abs(got - want)[inside].max()


@pytest.mark.parametrize("config", CONFIGS)
def test_q15_within_one_lsb_of_double(records, host, config):
    i = CONFIGS.index(config)
    worst = q15_vs_double(host, i, bank_of(records[config]), 1.0, OUT_FS[config],
                          stimulus(60_000, seed=i))
    print(f"{config}: Q15 within {worst:.3f} LSB of double")
    assert worst <= 1.0


@pytest.mark.parametrize("config", CONFIGS)
def test_float_close_to_double(records, host, config):
    bank = bank_of(records[config])
    u = stimulus(60_000, seed=10 + CONFIGS.index(config)).astype(np.float32)
    got = host.run(host.new("float", CONFIGS.index(config), "bank"), u).astype(float)
    want = bank.run(u.astype(float))
    rel = np.abs(got - want).max() / np.abs(want).max()
    print(f"{config}: float within {rel:.2g} of double (of the peak)")
    assert rel <= 1e-5


def synthetic_bank(fs):
    """A system with two lightly damped complex pairs (one within 1e-6 of
    z = 1), a negative real pole and a slow real one."""
    z = [0.999999 * np.exp(1j * 2e-6), 0.97 * np.exp(1j * 0.3)]
    blocks = [np.array([[p.real, -p.imag], [p.imag, p.real]]) for p in z]
    a = np.zeros((6, 6))
    a[0:2, 0:2], a[2:4, 2:4] = blocks
    a[4, 4], a[5, 5] = -0.6, 1 - 3e-8
    rng = np.random.default_rng(5)
    t = np.eye(6) + 0.3 * rng.standard_normal((6, 6))      # not in modal form
    b = np.array([[1e-6], [2e-6], [0.01], [0.02], [0.3], [1e-7]])
    c = np.array([[0.5, 0.2, 0.4, -0.3, 0.2, 0.6]])
    ti = np.linalg.inv(t)
    return realise(t @ a @ ti, t @ b, c @ ti, np.array([[0.05]]), fs)


def test_pairs_q15_and_float(tmp_path):
    bank = synthetic_bank(FS)
    assert len(bank.alpha) == 2 and len(bank.lam) == 2
    in_fs, out_fs = 1.0, 2.0
    (tmp_path / "syn_q15.h").write_text(
        export.header("syn_q15", "q15", fixed.q15(bank, in_fs, out_fs), ["synthetic"]))
    (tmp_path / "syn_f32.h").write_text(
        export.header("syn_f32", "float", fixed.f32(bank), ["synthetic"]))
    so = build_host_table(write_table([("syn_q15", "bank", "q15"),
                                       ("syn_f32", "bank", "float")], tmp_path), tmp_path)
    runner = HostRunner(LIB, so)
    u = stimulus(80_000, seed=7)
    worst = q15_vs_double(runner, 0, bank, in_fs, out_fs, u)
    print(f"pairs: Q15 within {worst:.3f} LSB of double")
    assert worst <= 1.0
    uf = u.astype(np.float32)
    got = runner.run(runner.new("float", 0, "bank"), uf).astype(float)
    want = bank.run(uf.astype(float))
    assert np.abs(got - want).max() <= 1e-5 * np.abs(want).max()
    # the closed-form step response and the double run agree
    n = np.arange(5000)
    assert np.allclose(bank.step(n), bank.run(np.ones(5000)), rtol=0, atol=1e-12)


def test_dead_time_delays_exactly(tmp_path):
    ds = [Design("dt_q15", "dd", "q15", kind="bank", effects=("deadtime:t=0.0031",)),
          Design("nodt_q15", "dd", "q15", kind="bank")]
    runner = _hosts(ds, tmp_path)
    u = (stimulus(5000, seed=3) * 32767).astype(np.int16)
    delayed = runner.run(runner.new("q15", 0, "bank"), u)
    plain = runner.run(runner.new("q15", 1, "bank"), u)
    assert np.all(delayed[:62] == 0) and np.array_equal(delayed[62:], plain[:-62])


def cannot(capsys, *args, config="dd", fs=FS):
    """pneufrac-reduce's main() in this process (argparse's own errors end
    in SystemExit): (exit status, stderr); nothing on stdout, one line on
    stderr."""
    try:
        rc = cli.main(["--config", config, "--fs", str(fs), "--format", "json", *args])
    except SystemExit as exc:
        rc = exc.code
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1, err
    return rc, err


@pytest.mark.parametrize("effect", ["backlash:width=0.01", "nozzle:xh=0.1",
                                    "saturation:lo=-0.01,hi=0.01"])
def test_in_loop_effects_are_refused(capsys, effect):
    rc, err = cannot(capsys, "--effect", effect)
    assert rc == 4 and "inside the loop" in err


def test_integrating_design_is_refused(capsys):
    rc, err = cannot(capsys, "--set", "q=1", config="id", fs=1000)
    assert rc == 4 and "stable" in err


def test_unreachable_tolerance_is_refused(capsys):
    rc, err = cannot(capsys, "--max-order", "3")
    assert rc == 4 and "no order up to 3" in err


@pytest.mark.parametrize("args", [
    ("--tol", "0"), ("--tol", "nan"), ("--horizon", "5:1"), ("--horizon", "1"),
    ("--name", "1abc"), ("--set", "bogus=1"), ("--set", "w=0.5"), ("--set", "q=inf"),
    ("--fs", "-1"), ("--max-order", "99"), ("--max-order", "2.5"), ("--order", "0"),
    ("--effect", "lag:t=1"), ("--effect", "wobble:x=1"), ("--in-fs", "1"),
    ("--arith", "float", "--out-fs", "1", "--in-fs", "1"), ("--set", "q=7"),
    ("--horizon", "0:100000"),
])
def test_bad_arguments(capsys, args):
    rc, err = cannot(capsys, *args)
    assert rc == 2 and err.startswith("pneufrac-reduce: error:")


def test_the_command_runs_as_installed():
    """The entry point itself, once: exit status and one line on stderr."""
    r = reduce_cli("--config", "dd", "--fs", FS, "--format", "json", "--tol", "2", check=False)
    assert r.returncode == 2 and r.stdout == "" and len(r.stderr.splitlines()) == 1


def test_header_compiles_as_c99_and_cxx20(tmp_path):
    hdr = reduce_cli("--config", "pid", "--fs", FS, "--in-fs", "1", "--out-fs", "20",
                     "--name", "pid_bank").stdout
    (tmp_path / "pid_bank.h").write_text(hdr)
    (tmp_path / "use.c").write_text('#include "pid_bank.h"\nconst void *p = &pid_bank;\n')
    for cc, std, src in (("cc", "-std=c99", "use.c"), ("g++", "-std=c++20", "use.cpp")):
        if src.endswith("cpp"):
            (tmp_path / src).write_text((tmp_path / "use.c").read_text())
        subprocess.run([cc, std, "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
                        f"-I{ROOT / 'lib' / 'include'}", f"-I{tmp_path}", str(tmp_path / src)],
                       check=True)
