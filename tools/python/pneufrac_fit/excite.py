# SPDX-License-Identifier: MIT
"""Excitation signals for synthetic records: steps, PRBS, ramps, sine
sweeps. Each opens with `rest` seconds at zero unless rest = 0 (an input
that never rests)."""
from __future__ import annotations

import numpy as np

KINDS = ("steps", "prbs", "ramps", "sweep")


def steps(n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
          hold=(0.06, 0.4), rest: float = 0.1, min_step: float = 0.15) -> np.ndarray:
    """Random steps of varied amplitude and sign, after a rest at zero.

    Levels are uniform in [-amp, amp]; consecutive levels differ by at least
    min_step*amp, so both small and large rises and falls occur."""
    e = np.zeros(n)
    i = int(round(rest * fs))
    level = 0.0
    while i < n:
        while True:
            new = rng.uniform(-amp, amp)
            if abs(new - level) >= min_step * amp:
                break
        level = new
        k = max(1, int(round(rng.uniform(*hold) * fs)))   # fs < 1/hold: 1 sample
        e[i:i + k] = level
        i += k
    return e


def prbs(n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
         clock: float = 0.02, rest: float = 0.1) -> np.ndarray:
    """Pseudo-random binary sequence between -amp/2 and +amp (asymmetric, so
    that level-dependent effects show), switching on a clock of `clock` s
    with probability 1/2."""
    e = np.zeros(n)
    i = int(round(rest * fs))
    k = max(1, int(round(clock * fs)))
    level = amp
    while i < n:
        if rng.uniform() < 0.5:
            level = -0.5 * amp if level > 0 else amp
        e[i:i + k] = level
        i += k
    return e


def ramps(n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
          dur=(0.1, 0.5), rest: float = 0.1) -> np.ndarray:
    """Straight lines between random levels in [-amp, amp], some of them
    held for a while (a setpoint sequence with ramped changes)."""
    e = np.zeros(n)
    i = int(round(rest * fs))
    level = 0.0
    while i < n:
        new = rng.uniform(-amp, amp)
        k = max(2, int(round(rng.uniform(*dur) * fs)))
        e[i:i + k] = np.linspace(level, new, k + 1)[1:][:n - i]
        i += k
        level = new
        if rng.uniform() < 0.5:            # hold the level for a while
            h = max(1, int(round(rng.uniform(*dur) * fs)))
            e[i:i + h] = level
            i += h
    return e


def sweep(n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
          f0: float = 0.1, f1: float = 5.0, rest: float = 0.0,
          offset: float = 0.0) -> np.ndarray:
    """Logarithmic sine sweep from f0 to f1 Hz over the record (after the
    rest), around `offset`, starting at a random phase."""
    e = np.full(n, offset)
    i = int(round(rest * fs))
    m = n - i
    if m <= 1:
        return e
    T = m / fs
    t = np.arange(m) / fs
    k = np.log(f1 / f0) / T
    phase = 2 * np.pi * f0 * (np.exp(k * t) - 1) / k + rng.uniform(0, 2 * np.pi)
    e[i:] = offset + amp * np.sin(phase)
    return e


def make(kind: str, n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
         rest: float = 0.1) -> np.ndarray:
    if kind == "steps":
        return steps(n, fs, rng, amp, rest=rest)
    if kind == "prbs":
        return prbs(n, fs, rng, amp, rest=rest)
    if kind == "ramps":
        return ramps(n, fs, rng, amp, rest=rest)
    if kind == "sweep":
        return sweep(n, fs, rng, amp, rest=rest)
    raise ValueError(f"unknown input kind {kind!r} (one of {', '.join(KINDS)})")
