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

Long memory (with_long_memory, used by the sandwich only). An AR model of
finite order has a flat spectrum at the lowest frequencies; 1/f-like noise
does not, and the power it has there is what the slow directions of a fit
(gain, offset, slow responses) absorb, so the residual's AR model
understates their variance (coverage28: 61 % coverage under 1/f noise).
The AR model's innovations are tested for a remaining power law
f(lam) ~ lam^(-2d) at the lowest frequencies (local Whittle, Robinson
1995); when d's own 95 % interval excludes 0 the noise is taken as
ARFIMA(p, d, 0) (Granger and Joyeux 1980, Hosking 1981), A(q) v = w with
w fractional noise, and the sandwich uses its exact autocovariance, whose
power law extrapolates the spectrum to the frequencies the fit absorbed.
Otherwise d = 0 and everything is as without it (white and AR records keep
their intervals).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.signal import fftconvolve, lfilter
from scipy.special import gammaln

P_MAX = 24            # highest AR order tried
MAX_ROOT = 0.999      # roots pulled inside this radius (a unit root is drift)
# Local Whittle bandwidth: the lowest m = n^LW_EXP Fourier frequencies, the
# bandwidth of Geweke and Porter-Hudak (1983); inside Robinson's (1995)
# conditions (m -> inf, m/n -> 0), and low enough that the AR model's
# innovations, flat where the AR model fits, show the power law that remains
# at the bottom of the spectrum (at n^0.65 they did not: coverage 51-77 %
# in the Monte Carlo of docs/analysis-bench.md, branch interval29).
LW_EXP = 0.5
LW_MIN = 8            # fewer frequencies than this: no test (d = 0)
D_MAX = 0.49          # d used at most this: fractional noise is stationary for d < 1/2


@dataclass
class NoiseModel:
    a: np.ndarray         # [1, a1, ..., ap]
    sigma2: float         # innovation variance
    var: float            # variance of the residual it was fitted to
    n: int
    d: float = 0.0        # long-memory exponent (0: none; with_long_memory)
    d_est: float | None = None   # local Whittle estimate and its sd, when tested
    d_sd: float | None = None

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
            text = "white (no AR term earns its place by BIC)"
        else:
            rho1 = _acf1(self.a)
            text = (f"AR({self.order}), lag-1 correlation {rho1:+.2f}, process variance "
                    f"{self.colour_factor():.3g}x the innovation variance")
        if self.d > 0:
            used = f", {self.d:.2f} used" if self.d < self.d_est else ""
            text += (f"; long memory d = {self.d_est:.2f} +- {1.96 * self.d_sd:.2f}{used} "
                     f"(power ~ f^-{2 * self.d:.2f} at the lowest frequencies)")
        return text


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


def local_whittle(x: np.ndarray, m: int) -> tuple[float, float]:
    """Robinson's (1995) local Whittle estimate of d from the lowest m
    Fourier frequencies of x (spectrum ~ G lam^(-2d) there), and its
    asymptotic sd 1/(2 sqrt(m)). The objective, G profiled out:
    R(d) = log(mean(lam_j^(2d) I_j)) - 2d mean(log lam_j)."""
    n = x.size
    I = np.abs(np.fft.rfft(x - np.mean(x))[1:m + 1]) ** 2
    ll = np.log(2.0 * np.pi * np.arange(1, m + 1) / n)
    dl = ll - ll.mean()

    def R(d):
        return math.log(float(np.mean(np.exp(2.0 * d * dl) * I)))
    d = minimize_scalar(R, bounds=(-0.49, 0.99), method="bounded", options={"xatol": 1e-4}).x
    return float(d), 0.5 / math.sqrt(m)


def frac_diff(x: np.ndarray, d: float) -> np.ndarray:
    """(1 - q^-1)^d x from rest (the binomial series cut at the record's
    start), by FFT convolution."""
    k = np.arange(1, x.size)
    c = np.r_[1.0, np.cumprod((k - 1.0 - d) / k)]
    return fftconvolve(x, c)[:x.size]


def frac_acov(d: float, n: int) -> np.ndarray:
    """Autocovariance at lags 0..n-1 of fractional noise (1 - q^-1)^-d eps,
    unit innovation variance (Hosking 1981): gamma0 = G(1-2d)/G(1-d)^2,
    rho_k = rho_(k-1) (k-1+d)/(k-d)."""
    k = np.arange(1, n)
    g0 = math.exp(gammaln(1.0 - 2.0 * d) - 2.0 * gammaln(1.0 - d))
    return g0 * np.r_[1.0, np.cumprod((k - 1.0 + d) / (k - d))]


def with_long_memory(nm: NoiseModel, r: np.ndarray) -> NoiseModel:
    """nm (an AR model of the residual r) with a long-memory exponent d
    when r's AR innovations show one: d by local Whittle on the innovations
    A(q) r, used when its 95 % interval excludes 0 (a one-sided test at
    2.5 %: white and AR records keep d = 0, so their intervals are the AR
    sandwich's), capped at D_MAX; the innovation variance is then that of
    (1 - q^-1)^d A(q) r."""
    e = lfilter(nm.a, [1.0], np.asarray(r, float) - np.mean(r))[nm.order:]
    m = int(e.size ** LW_EXP)
    if m < LW_MIN:
        return nm
    d, sd = local_whittle(e, m)
    out = NoiseModel(nm.a, nm.sigma2, nm.var, nm.n, 0.0, d, sd)
    if d - 1.96 * sd <= 0:
        return out
    out.d = min(d, D_MAX)
    eps = frac_diff(e - np.mean(e), out.d)
    out.sigma2 = float(eps @ eps) / eps.size
    return out


def _toeplitz_gram(G: np.ndarray, g: np.ndarray) -> np.ndarray:
    """G' T G with T the symmetric Toeplitz matrix of first column g: T G
    by the circulant embedding of size 2n (FFT), exact."""
    n = G.shape[0]
    c = np.r_[g, 0.0, g[:0:-1]]
    TG = np.fft.irfft(np.fft.rfft(c)[:, None] * np.fft.rfft(G, c.size, axis=0), c.size, axis=0)[:n]
    return G.T @ TG


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
    is 1/A run backwards in time over each column. With long memory (nm.d >
    0) S = sigma2 H T_d H', T_d the fractional noise's autocovariance
    matrix. Directions J does not determine get infinite variance."""
    U, S, Vt = np.linalg.svd(J, full_matrices=False)
    p = J.shape[1]
    tol = S.max() * 1e-9 if S.size and S.max() > 0 else 1.0
    keep = S > tol
    Jp = (Vt[keep].T / S[keep] ** 2) @ Vt[keep]          # (J'J)^+
    G = lfilter([1.0], nm.a, J[::-1], axis=0)[::-1]      # H' J
    M = nm.sigma2 * (_toeplitz_gram(G, frac_acov(nm.d, G.shape[0])) if nm.d > 0 else G.T @ G)
    cov = Jp @ M @ Jp
    null = ~keep
    if null.any():
        bad = np.any(np.abs(Vt[null]) > 1e-3, axis=0)
        cov[bad, :] = np.inf
        cov[:, bad] = np.inf
    return cov
