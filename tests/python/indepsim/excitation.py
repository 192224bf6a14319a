# SPDX-License-Identifier: MIT
"""Inputs e(t) as functions of continuous time (deviation from the
operating point), each drawn from a seeded generator and described by a
plain dict for the truth file. Steps fall anywhere in time, not on the
data grid.
"""
from __future__ import annotations

import math

import numpy as np

KINDS = ("steps", "prbs", "ramps", "sweep", "setpoint", "never_rest")


def _rest(rng: np.random.Generator) -> float:
    return float(rng.uniform(0.2, 0.5))


def steps(rng, amp: float, duration: float) -> dict:
    """Random steps: holds 0.1-0.6 s, levels in [-amp, amp], consecutive
    levels at least 0.2 amp apart, after a rest."""
    t, times, levels, last = _rest(rng), [], [], 0.0
    while t < duration:
        lv = last
        while abs(lv - last) < 0.2 * amp:
            lv = float(rng.uniform(-amp, amp))
        times.append(t)
        levels.append(lv)
        last = lv
        t += float(rng.uniform(0.1, 0.6))
    return {"kind": "steps", "amp": amp, "times": times, "levels": levels}


def _lfsr(order: int, n: int, seed: int) -> np.ndarray:
    """Maximal-length sequence from a Fibonacci LFSR (taps from Xilinx
    XAPP052, table 3)."""
    taps = {7: (7, 6), 8: (8, 6, 5, 4), 9: (9, 5), 10: (10, 7)}[order]
    state = seed % ((1 << order) - 1) + 1
    out = np.empty(n, dtype=int)
    for i in range(n):
        out[i] = state & 1
        fb = 0
        for tp in taps:
            fb ^= (state >> (order - tp)) & 1
        state = (state >> 1) | (fb << (order - 1))
    return out


def prbs(rng, amp: float, duration: float) -> dict:
    """PRBS between -amp and +amp, bit period 20-80 ms, after a rest."""
    t0, tb = _rest(rng), float(rng.uniform(0.02, 0.08))
    order = int(rng.choice([7, 8, 9]))
    nbits = int(math.ceil((duration - t0) / tb)) + 1
    bits = _lfsr(order, nbits, int(rng.integers(1, 1 << 20)))
    levels = list(np.where(bits > 0, amp, -amp).astype(float))
    times = [t0 + i * tb for i in range(nbits)]
    return {"kind": "prbs", "amp": amp, "bit_period": tb, "lfsr_order": order,
            "times": times, "levels": levels}


def ramps(rng, amp: float, duration: float) -> dict:
    """Ramps of 0.1-1 s between levels in [-amp, amp], holds of 0-0.5 s."""
    t, knots_t, knots_v, v = _rest(rng), [0.0], [0.0], 0.0
    knots_t.append(t)
    knots_v.append(0.0)
    while t < duration:
        t += float(rng.uniform(0.1, 1.0))
        v = float(rng.uniform(-amp, amp))
        knots_t.append(t)
        knots_v.append(v)
        t += float(rng.uniform(0.0, 0.5))
        knots_t.append(t)
        knots_v.append(v)
    return {"kind": "ramps", "amp": amp, "knots_t": knots_t, "knots_v": knots_v}


def sweep(rng, amp: float, duration: float, f0: float = 0.1, f1: float = 5.0) -> dict:
    """Logarithmic sine sweep f0 -> f1 over the record, from t = 0: no rest."""
    return {"kind": "sweep", "amp": amp, "f0": f0, "f1": f1, "duration": duration}


def setpoint(rng, amp: float, duration: float) -> dict:
    """The error of a closed loop after setpoint changes: each change of
    size dr adds dr exp(-t/Tc) cos(2 pi t / Tp) (a damped settling);
    changes every 1-3 s after a rest."""
    t, times, sizes = _rest(rng), [], []
    while t < duration:
        times.append(t)
        sizes.append(float(rng.uniform(0.4, 1.0) * amp * rng.choice([-1, 1])))
        t += float(rng.uniform(1.0, 3.0))
    return {"kind": "setpoint", "amp": amp, "times": times, "sizes": sizes,
            "t_settle": float(rng.uniform(0.2, 0.8)), "t_period": float(rng.uniform(1.0, 3.0))}


def never_rest(rng, amp: float, duration: float) -> dict:
    """A sum of 20 sines, frequencies log-uniform in 0.05-8 Hz, amplitudes
    ~ f^-1/2, scaled to a peak of amp; it runs from 3 s before the record
    (faded in from rest over the first second), so the record opens in
    the middle of operation."""
    f = np.exp(rng.uniform(math.log(0.05), math.log(8.0), 20))
    ph = rng.uniform(0.0, 2.0 * math.pi, 20)
    a = f ** -0.5
    tt = np.linspace(0.0, duration, 20001)
    peak = np.max(np.abs((a[None, :] * np.sin(2 * math.pi * f[None, :] * tt[:, None] + ph)).sum(1)))
    return {"kind": "never_rest", "amp": amp, "freqs": list(map(float, f)),
            "phases": list(map(float, ph)), "weights": list(map(float, a * amp / peak)),
            "pre_roll": 3.0}


def draw(kind: str, rng: np.random.Generator, amp: float, duration: float) -> dict:
    return {"steps": steps, "prbs": prbs, "ramps": ramps, "sweep": sweep,
            "setpoint": setpoint, "never_rest": never_rest}[kind](rng, amp, duration)


def pre_roll(spec: dict) -> float:
    return float(spec.get("pre_roll", 0.0))


def evaluate(spec: dict, t: np.ndarray) -> np.ndarray:
    """e(t) - e0 at the times t (t < 0 only for a pre-roll)."""
    k = spec["kind"]
    t = np.asarray(t, dtype=float)
    if k in ("steps", "prbs"):
        idx = np.searchsorted(np.asarray(spec["times"]), t, side="right") - 1
        lv = np.concatenate(([0.0], spec["levels"]))
        return lv[idx + 1]
    if k == "ramps":
        return np.interp(t, spec["knots_t"], spec["knots_v"])
    if k == "sweep":
        f0, f1, T = spec["f0"], spec["f1"], spec["duration"]
        r = math.log(f1 / f0)
        phase = 2 * math.pi * f0 * T / r * (np.exp(np.clip(t, 0, None) * r / T) - 1.0)
        return np.where(t >= 0, spec["amp"] * np.sin(phase), 0.0)
    if k == "setpoint":
        out = np.zeros_like(t)
        for tk, dr in zip(spec["times"], spec["sizes"]):
            u = t - tk
            on = u >= 0
            out[on] += dr * np.exp(-u[on] / spec["t_settle"]) * np.cos(2 * math.pi * u[on] / spec["t_period"])
        return out
    if k == "never_rest":
        f, ph, w = (np.asarray(spec[x]) for x in ("freqs", "phases", "weights"))
        out = np.zeros_like(t)
        for fi, pi, wi in zip(f, ph, w):
            out += wi * np.sin(2 * math.pi * fi * t + pi)
        t0 = -spec["pre_roll"]
        fade = np.clip(t - t0, 0.0, 1.0)
        return out * (0.5 - 0.5 * np.cos(math.pi * fade))
    raise ValueError(f"unknown excitation {k}")
