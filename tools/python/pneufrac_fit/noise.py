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

Long memory (fit_arfima, used by the sandwich). An AR model of finite
order has a flat spectrum at the lowest frequencies; 1/f-like noise does
not, and the power it has there is what the slow directions of a fit (gain,
offset, slow responses) absorb, so the residual's AR model understates
their variance (coverage28: 61 % coverage under 1/f noise). fit_arfima
models the residual as ARFIMA(p, d, 0) (Granger and Joyeux 1980, Hosking
1981), A(q) (1 - q^-1)^d v = eps, with (a, d) estimated jointly by Whittle's
likelihood (Fox and Taqqu 1986), and the sandwich uses its exact
autocovariance, whose power law extrapolates the spectrum to the
frequencies the fit absorbed. Short-memory noise gives d near 0 (the AR
sandwich, nearly), so no test decides whether d is used (branch arfima30:
a test's misses kept the AR model's coverage, about 50 %, on fractional
noise).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.signal import fftconvolve, lfilter
from scipy.special import gammaln

P_MAX = 24            # highest AR order tried
MAX_ROOT = 0.999      # roots pulled inside this radius (a unit root is drift)
D_MAX = 0.49          # d used at most this: fractional noise is stationary for d < 1/2
D_GRID = 50           # points of fit_arfima's grid over [0, D_MAX] (a step of 0.01)


@dataclass
class NoiseModel:
    a: np.ndarray         # [1, a1, ..., ap]
    sigma2: float         # innovation variance
    var: float            # variance of the residual it was fitted to
    n: int
    d: float = 0.0        # long-memory exponent (0: none; fit_arfima)
    d_sd: float | None = None    # its sd (Whittle information), when estimated
    spread: tuple = ()    # (weight, a, sigma2, d) over d's error: the sandwich's (fit_arfima)
    kurt: float = 3.0     # the innovations' kurtosis (noise.fit; 3: Gaussian)

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
        # Long memory is said only where d's own 95 % interval excludes 0:
        # a d^ of 0.01 +- 0.03 is what white noise gives on half its records.
        # Words only: the sandwich uses d^ either way (no gate, fit_arfima).
        if self.d > 0 and self.d - 1.96 * self.d_sd > 0:
            bound = " (at its bound: stationarity)" if self.d >= D_MAX else ""
            text += (f"; long memory d = {self.d:.2f} +- {1.96 * self.d_sd:.2f}{bound} "
                     f"(power ~ f^-{2 * self.d:.2f} at the lowest frequencies)")
        elif self.d > 0:
            text += f"; d = {self.d:.2f} +- {1.96 * self.d_sd:.2f}, not distinguishable from 0"
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


def _levinson(acov: np.ndarray):
    """The AR models of orders 0..len(acov)-1 that solve the autocorrelation
    (Yule-Walker) equations of acov, all at once by the Levinson-Durbin
    recursion: (p, [1, a1..ap], prediction error variance) per order, up to
    the first order whose error is not positive."""
    a = np.array([1.0])
    err = float(acov[0])
    yield 0, a, err
    for p in range(1, acov.size):
        k = -float(acov[1:p + 1][::-1] @ a) / err if err > 0 else 0.0
        b = np.zeros(p + 1)
        b[:p] = a
        b[1:] += k * a[::-1]
        a = b
        err *= (1.0 - k * k)
        if not err > 0:
            return
        yield p, a, err


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
    best = min(((n * math.log(max(err, 1e-300)) + p * math.log(n), a, err)
                for p, a, err in _levinson(acov)), key=lambda b: b[0])
    a = _stabilise(best[1])
    e = np.concatenate([lfilter(a, [1.0], x)[a.size - 1:] for x in pieces])
    s2 = float(e @ e) / max(e.size, 1)
    kurt = float(np.mean(e ** 4)) / (s2 * s2) if s2 > 0 else 3.0
    return NoiseModel(a, s2, var, n, kurt=kurt)


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


def _whittle_terms(x: np.ndarray, p_max: int):
    """The periodogram pieces of the Whittle likelihood of x: I_j = |X_j|^2/n
    at the Fourier frequencies lam_j = 2 pi j/n, j = 1..n/2 (the mean, j = 0,
    left out), L_j = log|1 - e^(i lam_j)|^2 (the fractional factor's log
    transfer), and cos(k lam_j), k = 0..p_max."""
    n = x.size
    I = (np.abs(np.fft.rfft(x - np.mean(x))) ** 2 / n)[1:]
    return (I, *_frequency_terms(n, p_max))


# The cosines take (p_max + 1) x n/2 doubles: a few MB at 10^5 samples, but
# hundreds of MB at 10^6, which a cache would keep after the diagnosis (the
# review of speed31). Above this size they are made per call, as before.
TERMS_CACHE_BYTES = 64 * 2**20


def _frequency_terms(n: int, p_max: int):
    """lam, L and the cosines of _whittle_terms: they depend on n and p_max
    alone, and a diagnosis fits every candidate's residual on the same fit
    part (the same n), where the (p_max + 1) x n/2 cosines cost about a
    third of a fit (branch speed31): kept per n up to TERMS_CACHE_BYTES,
    read only."""
    if 8 * (p_max + 1) * (n // 2) > TERMS_CACHE_BYTES:
        return _make_frequency_terms(n, p_max)
    return _kept_frequency_terms(n, p_max)


def _make_frequency_terms(n: int, p_max: int):
    lam = 2.0 * np.pi * np.arange(1, n // 2 + 1) / n
    L = 2.0 * np.log(2.0 * np.sin(lam / 2.0))
    C = np.cos(np.outer(np.arange(p_max + 1), lam))
    for a in (lam, L, C):
        a.flags.writeable = False
    return lam, L, C


_kept_frequency_terms = functools.lru_cache(maxsize=2)(_make_frequency_terms)


def fit_arfima(r, p_max: int = P_MAX) -> NoiseModel:
    """ARFIMA(p, d, 0) model of a residual, A(q) (1 - q^-1)^d v = eps
    (Granger and Joyeux 1980, Hosking 1981), (a, d) estimated jointly by
    Whittle's likelihood over all Fourier frequencies (Fox and Taqqu 1986;
    Beran 1994, ch. 5), p by BIC over the joint fits, d in [0, D_MAX].

    Why jointly: an AR model fitted first absorbs part of the low-frequency
    power, and a d estimated on its innovations then counts it again (about
    2x in se on fractional noise, branch interval29's review); a d tested
    first and used only when significant leaves long memory the test missed
    at the AR model's coverage (about 50 %).

    The Whittle objective with sigma2 profiled out is
        Q(a, d) = log mean_j(I_j |1 - e^(i lam_j)|^(2d) |A(e^(i lam_j))|^2)
                  - d mean_j(L_j),
    the mean of log|A|^2 dropped (0 for a monic causal A: Kolmogorov's
    formula). For a fixed d the first term is a quadratic form in a with the
    Toeplitz matrix of c_k = mean_j(I_j |1 - e^(i lam_j)|^(2d) cos(k lam_j)),
    the autocovariance of the fractionally differenced x: Levinson-Durbin
    gives its minimum over a for every order at once (a causal A, c being
    positive definite). So d is searched on a grid (every order's BIC at
    each point), and d refined by a bounded scalar search at the best order.
    BIC = n Q + (p + 1) log n, n Q being -2 log-likelihood (up to a constant)
    as in fit's BIC. d >= 0: the residual of a fit has lost low-frequency
    power to the fit's slow columns, which reads as anti-persistence
    (d < 0) and would narrow exactly the intervals of those columns.
    d's sd is from the Whittle information, W = (1/4 pi) int grad log f
    grad log f' dlam (Fox and Taqqu 1986): var(d^) = (W^-1)_dd / n."""
    x = np.asarray(r, float)
    n = x.size
    var = float(np.var(x)) if n else 0.0
    p_max = int(min(p_max, max(0, n // 20)))
    if n < 40 or not var > 0:
        return fit(x, p_max)
    I, lam, L, C = _whittle_terms(x, p_max)
    mL = float(np.mean(L))

    def orders(d):
        c = C @ (I * np.exp(d * L)) / I.size
        return [(n * (math.log(err) - d * mL) + (p + 1) * math.log(n), p, a, err)
                for p, a, err in _levinson(c)]

    grid = np.linspace(0.0, D_MAX, D_GRID)
    # the grid point and order of the least BIC
    best = min(((b, q, d) for d in grid for b, q, _, _ in orders(d)), key=lambda o: o[0])
    _, p, d0 = best
    step = grid[1] - grid[0]

    def Q(d):
        return next((o[0] for o in orders(d) if o[1] == p), math.inf)
    d = float(minimize_scalar(Q, bounds=(max(0.0, d0 - step), min(D_MAX, d0 + step)),
                              method="bounded", options={"xatol": 1e-4}).x)
    if Q(d) > Q(d0):
        d = float(d0)

    def at(d):      # the order-p model at d: a and sigma2 profiled
        _, _, a, s2 = next(o for o in orders(d) if o[1] == p)
        return _stabilise(a), float(s2)
    a, s2 = at(d)
    sd = _whittle_sd(a, d, lam, L, n)
    spread = tuple((w, *at(dk), dk) for w, dk in _d_nodes(d, sd))
    return NoiseModel(a, s2, var, n, d, sd, spread)


def _d_nodes(d: float, sd: float):
    """(weight, d) to average the sandwich over d's estimation error.

    Why: the variance of a slow direction's estimate depends on d steeply
    (a mean's variance grows like n^(2d - 1)); the plug-in at d^ leaves the
    intervals short where d^ comes out low: on ARFIMA(1, 0.3, 0), where d
    and the AR pole trade off, it covered 91 % (1000 draws, branch
    arfima30). So the variance is averaged over d ~ N(d^, sd^2), the
    Whittle estimate's asymptotic law, by the three-point Gauss-Hermite
    rule: d^ and d^ +- sqrt(3) sd, weights 2/3, 1/6, 1/6. This is a
    heuristic, calibrated by Monte Carlo (test_coverage), not a derivation:
    the variance is convex in d, so the average lies above the plug-in
    (Jensen) and widens the intervals at every d^. At each node A and
    sigma2 are the Whittle estimates given that d (the likelihood's ridge):
    d and A trade off at low frequencies, and A held at its estimate
    ignores that (on the AR(1) draws of test_coverage the mean's median se
    / rms error 1.17 with A held, 1.12 on the ridge, 1.07 for the AR model
    alone; branch arfima30).

    Near the bound d = 0 the normal law is not d^'s (Andrews 1999: a
    parameter on the boundary; d^ is exactly 0 on about half of white
    records), and a node clipped to 0 without its partner would move the
    nodes' mean above d^ and add long memory the estimate does not show
    (at d^ = 0 on white and AR(1) noise: a mean's variance 1.06-1.08x the
    AR model's, 20 seeds x 40 records, branch fixarf). So the spread is symmetric about d^ and kept inside d >= 0:
    half-width min(sqrt(3) sd, d^), no spread at d^ = 0, where the model is
    the AR one. At D_MAX (the stationarity limit, not a bound on the truth:
    1/f noise is d = 1/2) the upper node is clipped as before."""
    z = min(math.sqrt(3.0) * sd, d)
    if not z > 0:
        return ((1.0, d),)
    return tuple((w, min(d + k * z, D_MAX))
                 for w, k in ((2.0 / 3.0, 0), (1.0 / 6.0, -1), (1.0 / 6.0, 1)))


def _whittle_sd(a: np.ndarray, d: float, lam: np.ndarray, L: np.ndarray, n: int) -> float:
    """sd of d^ from the Whittle information of ARFIMA(p, d, 0): the
    gradient of log f is -L_j for d and -2 Re(e^(-ik lam) conj A)/|A|^2 for
    a_k; W = (1/2) mean over (0, pi) of its outer product."""
    k = np.arange(1, a.size)
    A = np.exp(-1j * np.outer(lam, np.arange(a.size))) @ a
    grad = np.vstack([-L] + [-2.0 * np.real(np.exp(-1j * kk * lam) * np.conj(A)) / np.abs(A) ** 2
                             for kk in k])
    W = 0.5 * (grad @ grad.T) / lam.size
    return float(math.sqrt(max(np.linalg.pinv(W)[0, 0], 0.0) / n))


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


def _gram(J: np.ndarray, a: np.ndarray, d: float) -> np.ndarray:
    """J' H T_d H' J (unit innovation variance): H'J is 1/A run backwards in
    time over each column; T_d the identity when d = 0."""
    G = lfilter([1.0], a, J[::-1], axis=0)[::-1]
    return _toeplitz_gram(G, frac_acov(d, G.shape[0])) if d > 0 else G.T @ G


def sandwich(J: np.ndarray, nm: NoiseModel) -> np.ndarray:
    """Covariance of the least-squares estimate whose residual Jacobian is
    J, when the noise is the AR process nm: (J'J)^+ J' S J (J'J)^+, with
    S = sigma2 H H' and H the lower-triangular Toeplitz matrix of 1/A. H'J
    is 1/A run backwards in time over each column. With long memory
    (fit_arfima's models) S = sigma2 H T_d H', T_d the fractional noise's
    autocovariance matrix, averaged over d's error (nm.spread, each node
    with its own A and sigma2). Directions J does not determine get
    infinite variance."""
    U, S, Vt = np.linalg.svd(J, full_matrices=False)
    p = J.shape[1]
    tol = S.max() * 1e-9 if S.size and S.max() > 0 else 1.0
    keep = S > tol
    Jp = (Vt[keep].T / S[keep] ** 2) @ Vt[keep]          # (J'J)^+
    M = sum(w * s2 * _gram(J, a, d) for w, a, s2, d in nm.spread or ((1.0, nm.a, nm.sigma2, nm.d),))
    cov = Jp @ M @ Jp
    null = ~keep
    if null.any():
        bad = np.any(np.abs(Vt[null]) > 1e-3, axis=0)
        cov[bad, :] = np.inf
        cov[:, bad] = np.inf
    return cov
