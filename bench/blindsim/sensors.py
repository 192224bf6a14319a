# SPDX-License-Identifier: MIT
"""The DAQ: sampling instants, sensor noise of several colours, an ADC.

Noise kinds (unit sd before scaling):
- white;
- ar2: a resonant AR(2), poles 0.97 at +-0.12 rad (pressure-transmitter
  ringing and pickup), not the AR(1) most tools assume;
- pink: 1/f spectrum shaped in the frequency domain;
- drift: white plus a slow random walk (about 40 % of the sd over a
  record) and a linear creep.
"""
from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

NOISE_KINDS = ("white", "ar2", "pink", "drift")


def noise(kind: str, n: int, rng: np.random.Generator) -> np.ndarray:
    w = rng.standard_normal(n)
    if kind == "white":
        v = w
    elif kind == "ar2":
        r, th = 0.97, 0.12
        v = lfilter([1.0], [1.0, -2 * r * np.cos(th), r * r], w)
    elif kind == "pink":
        spec = np.fft.rfft(w)
        f = np.arange(spec.size, dtype=float)
        f[0] = 1.0
        v = np.fft.irfft(spec / np.sqrt(f), n)
    elif kind == "drift":
        walk = np.cumsum(rng.standard_normal(n))
        walk -= walk[0]
        walk *= 0.4 / max(1e-12, np.std(walk))
        creep = np.linspace(0, rng.uniform(-0.5, 0.5), n)
        return w * 0.8 + walk + creep
    else:
        raise ValueError(f"unknown noise {kind}")
    return v / np.std(v)


def instants(n: int, fs: float, jitter: float, rng: np.random.Generator) -> np.ndarray:
    """Sampling instants k/fs, each off its grid point by up to jitter/fs."""
    t = np.arange(n) / fs
    if jitter > 0:
        t = t + rng.uniform(-jitter, jitter, n) / fs
    return t


def adc(v: np.ndarray, lo: float, hi: float, bits: int) -> np.ndarray:
    """Round to the converter's codes over [lo, hi] (clipped at its ends)."""
    if bits <= 0:
        return v
    step = (hi - lo) / (2 ** bits - 1)
    return lo + np.clip(np.round((v - lo) / step), 0, 2 ** bits - 1) * step
