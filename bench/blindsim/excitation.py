# SPDX-License-Identifier: MIT
"""Input signals e(t) (deviations from the operating point), as functions
of continuous time, so the plant's internal grid and the DAQ's jittered
sampling instants both see the same signal, and steps fall between grid
points wherever they happen to.

Every kind fills the whole record, so both the fit part and the held-out
part see the input move. `rest` seconds at the start hold e at 0 (a bump
test); `never_rest` kinds are used with a run-in before t = 0 instead.
"""
from __future__ import annotations

import numpy as np

KINDS = ("steps", "prbs", "ramps", "multisine", "setpoints", "wander")


def make(kind: str, rng: np.random.Generator, t_start: float, t_end: float,
         amp: float, rest: float = 0.0):
    """Return e(t), vectorised, for t in [t_start, t_end]."""
    span = t_end - t_start
    if kind == "steps":  # levels held 0.3-1.5 s, at instants off any grid
        times, levels, t = [], [], t_start + rest
        while t < t_end:
            times.append(t)
            levels.append(amp * rng.uniform(-1, 1))
            t += rng.uniform(0.3, 1.5)
        return _piecewise_constant(np.array(times), np.array(levels))
    if kind == "prbs":  # two levels, random clock multiple of 25-60 ms
        clock = rng.uniform(0.025, 0.06)
        n = int(span / clock) + 2
        bits = rng.integers(0, 2, n)
        bits[0] = 1
        times = t_start + rest + clock * np.arange(n)
        return _piecewise_constant(times, amp * (2 * bits - 1) * 0.7)
    if kind == "ramps":  # piecewise linear through random levels
        knots_t = [t_start, t_start + rest]
        knots_v = [0.0, 0.0]
        t = t_start + rest
        while t < t_end:
            t += rng.uniform(0.4, 2.0)
            knots_t.append(t)
            knots_v.append(amp * rng.uniform(-1, 1))
        kt, kv = np.array(knots_t), np.array(knots_v)
        return lambda tt: np.interp(tt, kt, kv)
    if kind == "multisine":  # 9 log-spaced tones 0.07-6 Hz, random phases
        f = np.geomspace(0.07, 6.0, 9)
        ph = rng.uniform(0, 2 * np.pi, f.size)
        a = amp / np.sqrt(f.size) * 1.2
        return lambda tt: np.sum(a * np.sin(2 * np.pi * f[:, None] * np.atleast_1d(tt)[None, :]
                                            + ph[:, None]), axis=0).reshape(np.shape(tt))
    if kind == "setpoints":  # a staircase up and back, each move a short ramp
        n = int(span / 1.2) + 2
        lv = amp * np.concatenate((np.linspace(-0.8, 0.9, n // 2), np.linspace(0.6, -0.9, n - n // 2)))
        lv += amp * 0.1 * rng.standard_normal(n)
        kt, kv = [t_start, t_start + rest], [0.0, 0.0]
        t = t_start + rest
        for v in lv:
            t += 0.05
            kt += [t, t + rng.uniform(0.8, 1.4)]
            kv += [v, v]
            t = kt[-1]
        kt, kv = np.array(kt), np.array(kv)
        return lambda tt: np.interp(tt, kt, kv)
    if kind == "wander":  # band-limited random signal: 40 tones 0.02-3 Hz, 1/f amplitudes
        f = np.geomspace(0.02, 3.0, 40)
        a = f ** -0.5
        a *= amp / np.sqrt(np.sum(a * a) / 2) * 0.6
        ph = rng.uniform(0, 2 * np.pi, f.size)
        return lambda tt: np.sum(a[:, None] * np.sin(2 * np.pi * f[:, None] * np.atleast_1d(tt)[None, :]
                                                     + ph[:, None]), axis=0).reshape(np.shape(tt))
    raise ValueError(f"unknown excitation {kind}")


def _piecewise_constant(times: np.ndarray, levels: np.ndarray):
    def e(tt):
        idx = np.searchsorted(times, tt, side="right") - 1
        return np.where(idx < 0, 0.0, levels[np.clip(idx, 0, None)])
    return e
