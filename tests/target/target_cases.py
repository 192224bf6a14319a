# SPDX-License-Identifier: MIT
"""On-target test cases: the cross-built library on emulated Cortex-M0+ and
Cortex-M4 cores (tools/mcuemu), against the host build, bit for bit.

The designs: every configuration at the library's defaults at 20 kHz
(dd is the paper's Example 6), a dd with effects and a dd with the nozzle
curve. For the full controller (kind "ctrl", pf_ctrl_*) the effects are
the Q15-capable ones (backlash, saturation, output lag, dead time) and the
nozzle case has the curve among the in-loop effects (its table searched
and solved on the target); for its reduced-order bank (kind "bank",
pf_bank_*, made by pneufrac-reduce at its defaults) the output line's
(lag, dead time: the in-loop ones, the nozzle among them, have no bank).
Q15 runs on both cores, float on the M4 (the M0+ has no FPU and its build
holds only the Q15 runtime).
"""
from __future__ import annotations

import numpy as np
from mcuemu.images import Design

CONFIGS = ("p", "dd", "id", "pid")
KINDS = ("ctrl", "bank")
# Output full scales that keep each configuration's step response inside
# Q15 for most of the stimulus, yet let the large steps saturate it.
OUT_FS = {"p": 0.02, "dd": 0.02, "id": 20.0, "pid": 20.0}
EFFECTS = {"ctrl": ("backlash:width=0.06", "saturation:lo=-0.01,hi=0.012", "lag:tau=0.002",
                    "deadtime:t=0.001"),
           "bank": ("lag:tau=0.002", "deadtime:t=0.001")}
# x_1/2 well inside the input's range: large steps drive x onto both flat
# ends of the curve, small ones stay near its operating point.
NOZZLE = ("nozzle:xh=0.2", "backlash:width=0.06", "saturation:lo=-0.01,hi=0.012")
# Index i of designs(arith, kind) is CASES[kind][i]; the nozzle sits in
# the loop, so only the full controller has it.
CASES = {"ctrl": list(CONFIGS) + ["fx", "nozzle"], "bank": list(CONFIGS) + ["fx"]}
KIND_CASES = [(kind, case) for kind in KINDS for case in CASES[kind]]


def designs(arith: str, kind: str = "ctrl") -> list[Design]:
    ds = [Design(f"t_{c}_{arith}_{kind}", c, arith, out_fs=OUT_FS[c], kind=kind)
          for c in CONFIGS]
    ds.append(Design(f"t_fx_{arith}_{kind}", "dd", arith, out_fs=OUT_FS["dd"],
                     effects=EFFECTS[kind], kind=kind))
    if "nozzle" in CASES[kind]:
        ds.append(Design(f"t_nozzle_{arith}_{kind}", "dd", arith, out_fs=OUT_FS["dd"],
                         effects=NOZZLE, kind=kind))
    return ds


def every_design(arith: str) -> list[Design]:
    return [d for kind in KINDS for d in designs(arith, kind)]


# (core, arithmetic) pairs that run on target
TARGETS = [("m0plus", "q15"), ("m4", "q15"), ("m4", "float")]
# Every on-target run: (core, arithmetic, bank_c, kind, case). bank_c is
# the M0+ build with the bank's portable C loop instead of its assembly
# one (lib/src/pf_bank_q15.c): both must equal the host's C bit for bit.
RUNS = [(core, arith, bank_c, kind, case)
        for core, arith in TARGETS for bank_c in ((False, True) if core == "m0plus" else (False,))
        for kind, case in KIND_CASES if kind == "bank" or not bank_c]


def run_id(run) -> str:
    core, arith, bank_c, kind, case = run
    return f"{core}{'-cloop' if bank_c else ''}-{arith}-{kind}-{case}"


def stimulus(arith: str, n: int, seed: int) -> np.ndarray:
    """A deterministic input that visits what a controller meets: steps of
    any size (full scale both ways included), ramps, sines from slow to
    near Nyquist, noise, long holds at zero (slow decay of every state),
    and for float, non-finite and extreme values (a failed sensor)."""
    rng = np.random.default_rng(seed)
    parts, total = [], 0
    while total < n:
        kind = rng.integers(0, 6)
        m = int(rng.integers(20, 3000))
        t = np.arange(m)
        amp = rng.uniform(-1.0, 1.0)
        if kind == 0:
            seg = np.full(m, amp)
        elif kind == 1:
            seg = np.full(m, rng.choice([-1.0, 1.0]))
        elif kind == 2:
            seg = np.linspace(rng.uniform(-1, 1), amp, m)
        elif kind == 3:
            seg = amp * np.sin(2 * np.pi * rng.uniform(1e-4, 0.45) * t)
        elif kind == 4:
            seg = np.clip(amp + 0.1 * rng.standard_normal(m), -1.0, 1.0)
        else:
            seg = np.zeros(m)
        parts.append(seg)
        total += m
    x = np.concatenate(parts)[:n]
    if arith == "q15":
        return np.clip(np.round(x * 32768.0), -32768, 32767).astype(np.int16)
    x = x.astype(np.float32)
    special = np.array([np.nan, np.inf, -np.inf, 3e38, -3e38, 1e-40, -0.0], dtype=np.float32)
    idx = rng.choice(n, size=min(n // 500 + 1, 40), replace=False)
    x[idx] = rng.choice(special, size=len(idx))
    return x


def same(a: np.ndarray, b: np.ndarray) -> bool:
    """Bit-exact equality (for float: the same bit patterns, NaN included)."""
    if a.dtype == np.float32:
        return np.array_equal(a.view(np.uint32), b.view(np.uint32))
    return np.array_equal(a, b)


def first_difference(a: np.ndarray, b: np.ndarray) -> str:
    bad = np.flatnonzero(a.view(np.uint32) != b.view(np.uint32)) if a.dtype == np.float32 \
        else np.flatnonzero(a != b)
    if len(bad) == 0:
        return "identical"
    i = bad[0]
    return f"{len(bad)} samples differ, first at {i}: target {a[i]!r}, host {b[i]!r}"
