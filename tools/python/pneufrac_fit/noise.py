# SPDX-License-Identifier: MIT
"""A noise model for the residual: what is left after the model is not
white when the sensor noise is coloured (AR, 1/f, drift). An AR model

    A(q) v = eps,   A(q) = 1 + a1 q^-1 + ... + ap q^-p,  eps white,

fitted to a residual (Yule-Walker, Levinson-Durbin), order chosen by BIC, gives
  - a whitening filter A(q) for likelihood-ratio comparisons of models
    (the same filter for both models compared);
  - the covariance of an output-error estimate under that noise (the
    sandwich (J'J)^-1 J' S J (J'J)^-1 with S the AR model's covariance),
    so that intervals hold under coloured noise;
  - the noise process's variance (not only its white part).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

P_MAX = 24            # highest AR order tried
MAX_ROOT = 0.999      # roots pulled inside this radius (a unit root is drift)


@dataclass
class NoiseModel:
    a: np.ndarray         # [1, a1, ..., ap]
    sigma2: float         # innovation variance
    var: float            # variance of the residual it was fitted to
    n: int

    @property
    def order(self) -> int:
        return self.a.size - 1

    def whiten(self, x: np.ndarray) -> np.ndarray:
        """A(q) x, the first p samples (no full history) dropped. x may be a
        matrix (columns filtered)."""
        y = lfilter(self.a, [1.0], x, axis=0)
        return y[self.order:]

    def colour_factor(self) -> float:
        """Process variance over innovation variance: sum of squares of the
        impulse response of 1/A (1 for white noise)."""
        h = lfilter([1.0], self.a, np.r_[1.0, np.zeros(4095)])
        return float(h @ h)

    def correlation_time(self) -> int:
        """Samples until the process's autocorrelation first falls under
        1/e (1 for white noise; at most the 4096 samples computed)."""
        h = lfilter([1.0], self.a, np.r_[1.0, np.zeros(4095)])
        acf = np.correlate(h, h, "full")[h.size - 1:] / float(h @ h)
        below = np.flatnonzero(acf < math.exp(-1.0))
        return int(below[0]) if below.size else h.size

    def describe(self) -> str:
        if self.order == 0:
            return "white (no AR term earns its place by BIC)"
        rho1 = _acf1(self.a)
        return (f"AR({self.order}), lag-1 correlation {rho1:+.2f}, process variance "
                f"{self.colour_factor():.3g}x the innovation variance")


def _acf1(a: np.ndarray) -> float:
    h = lfilter([1.0], a, np.r_[1.0, np.zeros(4095)])
    return float(h[1:] @ h[:-1] / (h @ h))


def _stabilise(a: np.ndarray) -> np.ndarray:
    """Pull the roots of A inside MAX_ROOT by scaling a_k by lam^k: the
    filter 1/A stays stable, and a random walk becomes a slow AR(1)."""
    if a.size <= 1:
        return a
    r = float(np.max(np.abs(np.roots(a))))
    if r <= MAX_ROOT:
        return a
    lam = MAX_ROOT / r
    return a * lam ** np.arange(a.size)


def fit(r, p_max: int = P_MAX) -> NoiseModel:
    """AR model of a residual, order 0..p_max by BIC: the autocorrelation
    (Yule-Walker) equations solved for every order at once by the Levinson-
    Durbin recursion, the autocorrelation from one FFT per piece. r is one
    array or a list of pieces (a record's fit parts): products never pair
    samples of two pieces, whose time apart is not their distance here."""
    pieces = [np.asarray(x, float) for x in (r if isinstance(r, (list, tuple)) else [r])]
    n = sum(x.size for x in pieces)
    mean = float(sum(np.sum(x) for x in pieces)) / n if n else 0.0
    pieces = [x - mean for x in pieces]
    p_max = int(min(p_max, max(0, n // 20)))
    var = float(sum(x @ x for x in pieces)) / max(n, 1)
    if p_max == 0 or not var > 0:
        return NoiseModel(np.array([1.0]), var, var, n)
    acov = np.zeros(p_max + 1)
    for x in pieces:
        nf = 1 << int(np.ceil(np.log2(2 * max(x.size, 1))))
        f = np.fft.rfft(x, nf)
        c = np.fft.irfft(f * np.conj(f), nf)[:min(p_max + 1, x.size)]
        acov[:c.size] += c
    acov /= n
    a = np.array([1.0])
    err = acov[0]
    best = (n * math.log(max(err, 1e-300)), a, err)
    for p in range(1, p_max + 1):
        k = -float(acov[1:p + 1][::-1] @ a) / err if err > 0 else 0.0
        a = np.r_[a, 0.0] + k * np.r_[0.0, a[::-1]]
        err *= (1.0 - k * k)
        if not err > 0:
            break
        bic = n * math.log(err) + p * math.log(n)
        if bic < best[0]:
            best = (bic, a.copy(), err)
    a = _stabilise(best[1])
    e = np.concatenate([lfilter(a, [1.0], x)[a.size - 1:] for x in pieces])
    s2 = float(e @ e) / max(e.size, 1)
    return NoiseModel(a, s2, var, n)


def whiten_parts(nm: NoiseModel | None, x: np.ndarray, parts) -> np.ndarray:
    """x's samples in parts (slices), each whitened by nm on its own (the
    filter restarts at every part's first sample: no whitened value mixes
    two parts), concatenated; without a noise model, the samples as they
    are. x may be a matrix (rows are samples)."""
    if nm is None:
        pieces = [x[s] for s in parts]
    else:
        pieces = [nm.whiten(x[s]) for s in parts]
    if not pieces:
        return x[:0]
    return np.concatenate(pieces)


def white(var: float, n: int) -> NoiseModel:
    return NoiseModel(np.array([1.0]), var, var, n)


def sandwich(J: np.ndarray, nm: NoiseModel) -> np.ndarray:
    """Covariance of the least-squares estimate whose residual Jacobian is
    J, when the noise is the AR process nm: (J'J)^+ J' S J (J'J)^+, with
    S = sigma2 H H' and H the lower-triangular Toeplitz matrix of 1/A. H'J
    is 1/A run backwards in time over each column. Directions J does not
    determine get infinite variance."""
    U, S, Vt = np.linalg.svd(J, full_matrices=False)
    p = J.shape[1]
    tol = S.max() * 1e-9 if S.size and S.max() > 0 else 1.0
    keep = S > tol
    Jp = (Vt[keep].T / S[keep] ** 2) @ Vt[keep]          # (J'J)^+
    G = lfilter([1.0], nm.a, J[::-1], axis=0)[::-1]      # H' J
    M = nm.sigma2 * (G.T @ G)
    cov = Jp @ M @ Jp
    null = ~keep
    if null.any():
        bad = np.any(np.abs(Vt[null]) > 1e-3, axis=0)
        cov[bad, :] = np.inf
        cov[:, bad] = np.inf
    return cov
