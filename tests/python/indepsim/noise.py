# SPDX-License-Identifier: MIT
"""Measurement noise and drift added to a sampled channel. Each generator
returns exactly the requested sample sd, so the truth file's level is the
level in the record."""
from __future__ import annotations

import math

import numpy as np
from scipy.signal import lfilter

MODELS = ("white", "ar1", "pink")


def _unit(x: np.ndarray) -> np.ndarray:
    x = x - x.mean()
    return x / x.std()


def white(n: int, rng: np.random.Generator) -> np.ndarray:
    return _unit(rng.standard_normal(n))


def ar1(n: int, phi: float, rng: np.random.Generator) -> np.ndarray:
    """n[k] = phi n[k-1] + eps[k], started in its stationary distribution."""
    if not -1.0 < phi < 1.0:
        raise ValueError("AR(1) coefficient must lie in (-1, 1)")
    eps = rng.standard_normal(n) * math.sqrt(1.0 - phi * phi)
    x0 = rng.standard_normal()
    return _unit(lfilter([1.0], [1.0, -phi], eps, zi=[phi * x0])[0])


def pink(n: int, rng: np.random.Generator) -> np.ndarray:
    """1/f power spectrum from the record's lowest frequency to Nyquist, by
    shaping white Gaussian spectral coefficients with f^-1/2."""
    m = n // 2 + 1
    f = np.arange(m, dtype=float)
    spec = (rng.standard_normal(m) + 1j * rng.standard_normal(m))
    spec[1:] /= np.sqrt(f[1:])
    spec[0] = 0.0
    return _unit(np.fft.irfft(spec, n))


def draw(model: str, n: int, rng: np.random.Generator, phi: float = 0.0) -> np.ndarray:
    """Unit-sd noise of the model."""
    if model == "white":
        return white(n, rng)
    if model == "ar1":
        return ar1(n, phi, rng)
    if model == "pink":
        return pink(n, rng)
    raise ValueError(f"unknown noise model {model}")


def drift(t: np.ndarray, amp: float, rng: np.random.Generator) -> tuple[np.ndarray, dict]:
    """Slow sensor drift: a linear trend plus a sine of period 2-4 times the
    record, scaled so that its range over the record is amp."""
    T = float(t[-1] - t[0]) or 1.0
    u = (t - t[0]) / T
    slope = float(rng.uniform(-1.0, 1.0))
    per = float(rng.uniform(2.0, 4.0))
    ph = float(rng.uniform(0.0, 2 * math.pi))
    d = slope * u + np.sin(2 * math.pi * u / per + ph)
    d -= d[0]
    rngd = float(d.max() - d.min()) or 1.0
    return d * (amp / rngd), {"range": amp, "trend": slope, "period_records": per, "phase": ph}
