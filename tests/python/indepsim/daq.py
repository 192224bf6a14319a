# SPDX-License-Identifier: MIT
"""What the data acquisition does to a continuous signal: sample it at
(possibly jittered) instants with an averaging front end, write time
stamps, quantise with an ADC.

Averaging: each sample is the mean of the signal over the sample period
ending at its instant, as an integrating or oversample-and-average DAQ
delivers (a boxcar anti-alias filter, the same on every channel, so it
adds the same half-sample delay to e and p_c)."""
from __future__ import annotations

import numpy as np

BITS = 12
STAMP_RESOLUTION = 1e-6   # s: the historian writes microseconds


def sample_times(n: int, fs: float, rng: np.random.Generator | None,
                 jitter_sd: float) -> np.ndarray:
    """Sampling instants k/fs, each off by N(0, jitter_sd) periods
    (clipped at 3 sd, so the order never changes) when jitter_sd > 0."""
    t = np.arange(n) / fs
    if jitter_sd > 0.0:
        j = np.clip(rng.standard_normal(n), -3.0, 3.0) * jitter_sd / fs
        t = t + j
    return t


def stamps(t: np.ndarray) -> np.ndarray:
    return np.round(t / STAMP_RESOLUTION) * STAMP_RESOLUTION


def average(sig: np.ndarray, t0: float, fs_int: float, t: np.ndarray, fs: float) -> np.ndarray:
    """Mean of the internally sampled signal (grid t0 + k/fs_int, linear
    between samples) over (t - 1/fs, t]."""
    grid = t0 + np.arange(sig.size) / fs_int
    cum = np.concatenate(([0.0], np.cumsum(0.5 * (sig[1:] + sig[:-1]) / fs_int)))
    return (np.interp(t, grid, cum) - np.interp(t - 1.0 / fs, grid, cum)) * fs


def adc_range(x: np.ndarray, use: float) -> tuple[float, float]:
    """An input range in which the signal spans the fraction `use`,
    centred on it (an instrument range chosen with head-room)."""
    lo, hi = float(np.min(x)), float(np.max(x))
    span = (hi - lo) or max(abs(hi), 1.0)
    full = span / use
    mid = 0.5 * (lo + hi)
    return mid - 0.5 * full, mid + 0.5 * full


def quantise(x: np.ndarray, lo: float, hi: float, bits: int = BITS) -> np.ndarray:
    """Mid-tread ADC: the nearest of 2^bits levels lo + k lsb, clipped."""
    lsb = (hi - lo) / (2 ** bits - 1)
    code = np.clip(np.round((x - lo) / lsb), 0, 2 ** bits - 1)
    return lo + code * lsb
