#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Reduced-order banks (pneufrac-reduce, lib pf_bank.h) of the four
configurations at 20 kHz: the order the rule reaches, its error against
the full design, the error against the exact response in double, float and
Q15, and Q15 against the same bank in double. Writes Markdown to stdout
(bench/run.sh puts it into docs/accuracy.md).

The float and Q15 figures are the C runtimes' (the host build, through
ctypes, on headers exported by pneufrac-reduce); the exact response is the
host library's (bench_accuracy --exact, tools/host/pfh_ref.c).
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from mcuemu.images import Design, build_host_sets, host_build_dir
from mcuemu.runner import HostRunner

from pneufrac_reduce.reduce import design, reduce_design

FS = 20000.0
CONFIGS = ("p", "dd", "id", "pid")
# The exact reference's case of each configuration at its defaults
# (tests/ref/paper_step_cases.json).
REF_CASE = {"p": "ex4_q0.9", "dd": "ex6_q0.9", "id": "ex7", "pid": "pid"}
TOL = 5e-4
# (horizon, tolerance) of each row of the orders table: the defaults, a
# horizon that leaves out the first millisecond, a tighter tolerance
VARIANTS = {"[0, 10] s, 0.05 % (default)": ((0.0, 10.0), TOL),
            "[1 ms, 10 s], 0.05 %": ((1e-3, 10.0), TOL),
            "[0, 10] s, 0.02 %": ((0.0, 10.0), 2e-4)}
WINDOW = (1e-3, 2.0)   # docs/accuracy.md's window against the exact response
# Q15 runs as docs/accuracy.md's: a half-scale step (in_fs = 2) with
# out_fs = 1.25 x the exact peak.
IN_FS_Q15 = 2.0


def exact(config: str) -> tuple[np.ndarray, np.ndarray]:
    """Sample indices and the exact step response over WINDOW."""
    r = subprocess.run([str(host_build_dir() / "bench" / "bench_accuracy"), "--exact",
                        REF_CASE[config], repr(FS), repr(WINDOW[0]), repr(WINDOW[1])],
                       capture_output=True, text=True, check=True)
    v = np.loadtxt(r.stdout.splitlines())
    return v[:, 0].astype(np.int64), v[:, 1]


def freq_error(ctrl, bank) -> float:
    """max over a log grid up to Nyquist of |H_bank - H_full| / max |H_full|."""
    a, b, c, d = ctrl.state_space()
    w = np.logspace(-4, np.log10(0.999 * np.pi * FS), 300)
    z = np.exp(1j * w / FS)
    h = np.array([(c @ np.linalg.solve(zz * np.eye(len(a)) - a, b))[0, 0] + d[0, 0] for zz in z])
    hb = bank.d + sum(bt * lam / (z - (1 - lam)) for lam, bt in zip(bank.lam, bank.beta))
    if len(bank.alpha):
        pb = bank.pair_input()
        for al, om, bb in zip(bank.alpha, bank.omega, pb):
            m = np.array([[1 - al, -om], [om, 1 - al]])
            hb = hb + np.array([np.linalg.solve(zz * np.eye(2) - m, bb)[0] for zz in z])
    return float(np.max(np.abs(hb - h)) / np.max(np.abs(h)))


def stimulus(n: int, seed: int, longest: int) -> np.ndarray:
    """Random levels held for 1 to @longest samples."""
    rng = np.random.default_rng(seed)
    return np.repeat(rng.uniform(-1, 1, n), rng.integers(1, longest + 1, n))[:n]


def orders_table() -> str:
    lines = ["| config | full design, states | horizon, tolerance | bank, states (real + 2 x pairs) "
             "| step error over the horizon | step error before it "
             "| frequency response error | fast input |",
             "|---|---|---|---|---|---|---|---|"]
    for i, c in enumerate(CONFIGS):
        ctrl = design(c, FS, {}, {})
        u = stimulus(100_000, seed=20 + i, longest=50)
        full = ctrl.run(u)
        for label, (hz, tol) in VARIANTS.items():
            red = reduce_design(ctrl, FS, hz, tol)
            b = red.bank
            fast = np.abs(b.run(u) - full).max() / np.abs(full).max()
            lines.append(f"| {c} | {red.full_order} | {label} | {b.order} ({len(b.lam)} + "
                         f"2 x {len(b.alpha)}) | {100 * red.error:.4f} % | "
                         + (f"{100 * red.error_before:.3f} %" if hz[0] > 0 else "-")
                         + f" | {100 * freq_error(ctrl, b):.3f} % | {100 * fast:.3f} % |")
    return "\n".join(lines)


def exact_table(work: Path) -> str:
    refs = {c: exact(c) for c in CONFIGS}
    peaks = {c: float(np.abs(refs[c][1]).max()) for c in CONFIGS}
    ds = [Design(f"x_{c}_q15", c, "q15", in_fs=IN_FS_Q15, out_fs=1.25 * peaks[c], kind="bank")
          for c in CONFIGS]
    ds += [Design(f"x_{c}_f32", c, "float", kind="bank") for c in CONFIGS]
    runner = HostRunner(host_build_dir() / "lib" / "libpneufrac.so", build_host_sets(ds, work))
    lines = ["| config | bank states | full design, double | bank, double | bank, float "
             "| bank, Q15 | Q15 against the bank in double (step; varied input) |",
             "|---|---|---|---|---|---|---|"]
    for i, c in enumerate(CONFIGS):
        n, y = refs[c]
        ctrl = design(c, FS, {}, {})
        bank = reduce_design(ctrl, FS, (0.0, 10.0), TOL).bank
        steps = np.ones(n[-1] + 1)
        full = ctrl.run(steps)[n]
        dbl = bank.run(steps)[n]
        flt = runner.run(runner.new("float", i, "bank"), steps.astype(np.float32))[n]
        out_fs = 1.25 * peaks[c]
        q = runner.run(runner.new("q15", i, "bank"), np.full(n[-1] + 1, 16384, np.int16))
        q15 = q[n] * out_fs / 32768.0
        lsb_step = np.abs(q[n] - dbl / out_fs * 32768.0).max()
        u = stimulus(100_000, seed=i, longest=400)
        uq = np.clip(np.round(u * 32768), -32768, 32767).astype(np.int16)
        got = runner.run(runner.new("q15", i, "bank"), uq).astype(float)
        want = bank.run(uq / 32768.0 * IN_FS_Q15) / out_fs * 32768.0
        inside = np.abs(want) < 32767
        lsb_var = np.abs(got - want)[inside].max()
        e = [np.abs(v - y).max() / peaks[c] for v in (full, dbl, flt, q15)]
        lines.append(f"| {c} | {bank.order} | " + " | ".join(f"{100 * x:.4f} %" for x in e)
                     + f" | {lsb_step:.2f} LSB; {lsb_var:.2f} LSB |")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.parse_args()
    print("Orders reached at 20 kHz, each configuration at the library's defaults (dd is "
          "Example 6), for pneufrac-reduce's default horizon and tolerance and two others. The "
          "step error is against the full design in double over the horizon; the frequency "
          "response error is max |H_bank - H_full| over 1e-4 rad/s to Nyquist, relative to "
          "max |H_full|; the fast input is 100 000 samples of random levels held 1 to 50 "
          "samples each, max |bank - full| relative to the full design's peak:\n")
    print(orders_table())
    print(f"\nAgainst the exact response, max |error| over t in [{WINDOW[0]:g}, {WINDOW[1]:g}] s "
          "relative to the peak, as in the tables above (the bank: default horizon and "
          "tolerance; Q15: a half-scale step, in_fs = 2, out_fs = 1.25 x the peak). Q15 "
          "against double: the step, and a held random input of 100 000 samples:\n")
    with tempfile.TemporaryDirectory() as tmp:
        print(exact_table(Path(tmp)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
