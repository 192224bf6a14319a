# SPDX-License-Identifier: MIT
"""On-target test cases: the cross-built library on emulated Cortex-M0+ and
Cortex-M4 cores (tools/mcuemu), against the host build, bit for bit.

The designs: every configuration at the library's defaults at 20 kHz
(dd is the paper's Example 6), a dd with the line and in-loop effects
(backlash, saturation, output lag, dead time), and a dd with the nozzle
curve among the in-loop effects (its table searched and solved on the
target). Q15 runs on both cores, float on the M4 (the M0+ has no FPU and
its build holds only the Q15 runtime).
"""
from __future__ import annotations

import numpy as np
from mcuemu.images import Design

CONFIGS = ("p", "dd", "id", "pid")
# Output full scales that keep each configuration's step response inside
# Q15 for most of the stimulus, yet let the large steps saturate it.
OUT_FS = {"p": 0.02, "dd": 0.02, "id": 20.0, "pid": 20.0}
EFFECTS = ("backlash:width=0.06", "saturation:lo=-0.01,hi=0.012", "lag:tau=0.002",
           "deadtime:t=0.001")
# x_1/2 well inside the input's range: large steps drive x onto both flat
# ends of the curve, small ones stay near its operating point.
NOZZLE = ("nozzle:xh=0.2", "backlash:width=0.06", "saturation:lo=-0.01,hi=0.012")


def designs(arith: str) -> list[Design]:
    ds = [Design(f"t_{c}_{arith}", c, arith, out_fs=OUT_FS[c]) for c in CONFIGS]
    ds.append(Design(f"t_fx_{arith}", "dd", arith, out_fs=OUT_FS["dd"], effects=EFFECTS))
    ds.append(Design(f"t_nozzle_{arith}", "dd", arith, out_fs=OUT_FS["dd"], effects=NOZZLE))
    return ds


CASES = [c for c in CONFIGS] + ["fx", "nozzle"]   # index i of designs() is CASES[i]
# (core, arithmetic) pairs that run on target
TARGETS = [("m0plus", "q15"), ("m4", "q15"), ("m4", "float")]


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
