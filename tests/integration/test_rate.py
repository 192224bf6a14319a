# SPDX-License-Identifier: MIT
"""The model at its own rate: substeps beyond the internal-rate limit are
refused as an invalid parameter; a set the loop could not run within
--loop-budget is refused at commit (exception 03, commit_result 7,
commit_err_addr naming substeps or fs) and at start (exit status 2).
The loads are predicted from the per-step and per-wake-up costs the
daemon itself measured, so each case is decided with a wide margin
whatever the machine's speed."""

import re
import subprocess

import pytest

from pfd import DAEMON, REG, Regs, wait_until

LOAD_REFUSED = 7


def wake_us(d):
    """The loop's wake-up cost the daemon measured at start."""
    return float(re.search(r"msg=loop-load .*wake_us=(\S+)", d.log()).group(1))


def predicted_pct(fs, k, step_ns, wake):
    """One instance: fs x (k + 1) x step and fs wake-ups, plus the same
    exchange over the same period (docs/pneufracd.md, "Loop budget")."""
    return 100 * fs * (2 * (k + 1) * step_ns * 1e-9 + wake * 1e-6)


def commit(r, **staged):
    """Stage and commit over one connection (staging is the connection's
    own); the exception code, or None."""
    for name, value in staged.items():
        r.write(name, value)
    resp = r.write_raw("commit", 1)
    return resp.exception_code if resp.isError() else None


def committed_image(r):
    return [r.read(n) for n in ("committed_fs", "committed_substeps", "substeps_used",
                                "internal_fs", "commits")]


def test_substeps_beyond_the_internal_limit(daemon):
    d = daemon("--clock", "external")
    r = Regs(d.client())
    before = committed_image(r)
    assert commit(r, fs=1000.0, substeps=201) == 3  # 201 kHz
    assert r.read("commit_result") == 1
    assert r.read("commit_err_addr") == REG["substeps"][1]
    assert r.read("commit_err_param") == 65535  # the daemon's own setting
    assert committed_image(r) == before
    assert commit(r, substeps=200) is None
    assert r.read("substeps_used") == 200 and r.read("internal_fs") == 200000.0


def test_commit_over_the_budget_is_refused(daemon):
    """Budget 1 %, free-running; the instance starts light (20 Hz, one
    substep)."""
    d = daemon("--arith", "q15", "--fs", "20", "--substeps", "1", "--loop-budget", "1")
    r = Regs(d.client())
    wake = wake_us(d)
    # pid in q15: the costliest step. Measured on a light set first.
    assert commit(r, config=3, out_fs=16.0) is None
    step = r.read("step_cost_ns")
    assert step > 0
    assert r.read("load_pct") == pytest.approx(100 * 20.0 * 2 * step * 1e-9, rel=1e-6)
    if predicted_pct(50000.0, 4, step, wake) < 4:
        pytest.skip(f"{step:.1f} ns a step, {wake:.1f} us a wake-up: too fast to exceed "
                    "1 % by 4x")
    before = committed_image(r)
    # 50 kHz x 4 substeps: refused, and the substeps are to blame.
    assert commit(r, fs=50000.0, substeps=4) == 3
    assert r.read("commit_result") == LOAD_REFUSED
    assert r.read("commit_err_addr") == REG["substeps"][1]
    assert r.read("status") & (1 << 2)
    assert committed_image(r) == before
    # One step per exchange at 50 kHz: the exchange rate is to blame.
    if predicted_pct(50000.0, 1, step, wake) >= 4:
        assert commit(r, substeps=1) == 3
        assert r.read("commit_result") == LOAD_REFUSED
        assert r.read("commit_err_addr") == REG["fs"][1]
    # A set far below the budget goes through, and runs.
    assert predicted_pct(40.0, 1, step, wake) < 0.25
    assert commit(r, fs=40.0, substeps=1) is None
    assert r.read("commit_result") == 0
    assert r.read("committed_fs") == 40.0
    wait_until(lambda: not r.read("status") & (1 << 8), 5, "the set switched in")
    s0 = r.read("samples")
    wait_until(lambda: r.read("samples") >= s0 + 3, 5, "samples at 40 Hz")


def test_lockstep_has_no_budget(daemon):
    """With --clock external the client's ticks set the pace: the same
    heavy set is accepted, and runs."""
    d = daemon("--clock", "external", "--arith", "q15", "--fs", "20", "--substeps", "1",
               "--loop-budget", "1")
    r = Regs(d.client())
    assert commit(r, config=3, out_fs=16.0, fs=50000.0, substeps=4) is None
    r.tick(10)
    assert r.read("samples") == 10 and r.read("substeps_used") == 4
    assert r.read("load_pct") > 0


def test_start_over_the_budget_is_refused():
    """64 q15 instances at 50 kHz with 4 substeps: 64 x 50000 x 5 steps a
    second, 16 % of a core even at 1 ns a step, against a budget of 1 %."""
    p = subprocess.run([DAEMON, "--listen", "127.0.0.1:0", "--run-for", "5",
                        "--instances", "64", "--fs", "50000", "--substeps", "4",
                        "--arith", "q15", "--loop-budget", "1"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, p.stderr
    last = p.stderr.strip().splitlines()[-1]
    assert last.startswith("pneufracd: the instances need ") and "--loop-budget 1 %" in last, last
    assert "msg=listening" not in p.stderr


def test_start_beyond_the_rules_rate(tmp_path):
    """Example 6 at a 1 Hz exchange rate: the rule wants 20 kHz inside, and
    10000 substeps give 10 kHz. Refused at start with the reason; with
    substeps given, the rate is the client's choice and it runs."""
    p = subprocess.run([DAEMON, "--fs", "1", "--listen", "127.0.0.1:0", "--run-for", "1"],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2
    assert p.stderr.startswith("pneufracd: instance 1: the substep rule needs an internal "
                               "rate beyond the limits (10000 substeps, 200000 Hz); give "
                               "substeps to choose the rate"), p.stderr
    p = subprocess.run([DAEMON, "--fs", "1", "--substeps", "10000", "--listen", "127.0.0.1:0",
                        "--run-for", "0.5"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert "substeps=10000 internal_fs=10000 " in p.stderr
