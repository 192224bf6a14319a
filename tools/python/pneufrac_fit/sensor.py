# SPDX-License-Identifier: MIT
"""What a sensor adds to a clean signal in synthetic records: white, AR(1),
resonant AR(2) or 1/f noise, slow drift, and ADC quantisation."""
from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

KINDS = ("white", "ar1", "ar2", "pink")
AR1_POLE = 0.95
# A resonant AR(2): a pair of poles at this radius and frequency (cycles
# per sample), as a sensor line with a mechanical or acoustic resonance
AR2_RADIUS = 0.99
AR2_FREQ = 0.01


def coloured(n: int, sd: float, kind: str, rng: np.random.Generator) -> np.ndarray:
    """Zero-mean noise of standard deviation sd (over the record)."""
    w = rng.standard_normal(n)
    if kind == "white":
        v = w
    elif kind == "ar1":
        v = lfilter([1.0], [1.0, -AR1_POLE], w)
    elif kind == "ar2":
        c = 2.0 * AR2_RADIUS * np.cos(2.0 * np.pi * AR2_FREQ)
        v = lfilter([1.0], [1.0, -c, AR2_RADIUS ** 2], w)
    elif kind == "pink":                     # 1/f power: amplitude ~ f^-1/2
        f = np.fft.rfftfreq(n)
        g = np.zeros_like(f)
        g[1:] = 1.0 / np.sqrt(f[1:])
        v = np.fft.irfft(np.fft.rfft(w) * g, n)
    else:
        raise ValueError(f"unknown noise kind {kind!r} (one of {', '.join(KINDS)})")
    v = v - v.mean()
    s = float(np.std(v))
    return v * (sd / s) if s > 0 else v


def drift(n: int, fs: float, size: float, rng: np.random.Generator) -> np.ndarray:
    """A slow wander of peak-to-peak `size`: two sines of periods a third
    and the whole of the record, random phases."""
    t = np.arange(n) / fs
    T = n / fs
    d = (np.sin(2 * np.pi * t / T + rng.uniform(0, 2 * np.pi))
         + 0.5 * np.sin(2 * np.pi * 3 * t / T + rng.uniform(0, 2 * np.pi)))
    d -= d[0]
    p = float(np.ptp(d))
    return d * (size / p) if p > 0 else d


def adc(v: np.ndarray, bits: int, lo: float, hi: float) -> np.ndarray:
    """Quantise to a converter of `bits` over [lo, hi] (clipped)."""
    q = (hi - lo) / (2 ** bits - 1)
    return lo + np.round((np.clip(v, lo, hi) - lo) / q) * q
