# SPDX-License-Identifier: MIT
"""The long-run variance of an AR noise model and its sampling error.

For A(q) v = eps (noise.NoiseModel: a = [1, a1, ..., ap], innovation
variance sigma2) the long-run variance is the spectrum at zero frequency
(x 2 pi), LRV = sigma2 / A(1)^2, A(1) = 1 + a1 + ... + ap: the variance
rate of the process's sums over long stretches, what weighs a slow
difference between two models' outputs.

Its sampling error, for the model fitted (Yule-Walker or least squares) to
n samples of the process: the coefficients are asymptotically normal with
covariance sigma2 Gamma_p^-1 / n, Gamma_p the p x p autocovariance matrix,
and the innovation variance independent of them with Var(sigma2_hat) =
(kappa - 1) sigma2^2 / n, kappa the innovations' kurtosis: 2 sigma2^2 / n
under Gaussian innovations (Brockwell and Davis, Time Series: Theory and
Methods, 2nd ed., Thm 8.1.1 and Sec. 8.8; Box, Jenkins and Reinsel, Sec.
7.2; the variance of a sample second moment). The measured kurtosis is
used, not 3: heavy-tailed noise (a spike, an ADC glitch) makes sigma2_hat
far less certain, and the Gaussian se let the test fire on t(3) noise in
1-8 % of draws (the review of branch noise30). By the delta method, with
d log LRV / d a_k = -2 / A(1) for every k,

    n Var(log LRV_hat) = (kappa - 1) + 4 (1' G^-1 1) / A(1)^2,

G the autocovariance matrix of the process with unit innovation variance
(sigma2 cancels). For AR(1) of pole phi: 2 + 4 (1 - phi^2) / (1 - phi)^2.
It is asymptotic: at a pole near 1 on a few hundred samples the estimate
is biased low (the Yule-Walker pole shrinks towards 0) and the normal
approximation is poor (measured: docs/analysis-bench.md, branch noise30).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import solve_toeplitz
from scipy.signal import lfilter


def variance(nm) -> float:
    """sigma2 / A(1)^2: the AR process's spectrum at zero frequency (x 2 pi)."""
    s = float(np.sum(nm.a))
    return nm.sigma2 / max(s * s, 1e-300)


def log_var_rate(nm) -> float:
    """n Var(log LRV_hat) for nm's AR model fitted to n samples of itself
    (the delta method above): kappa - 1 for white noise (2 if Gaussian)."""
    p = nm.a.size - 1
    if p == 0:
        return nm.kurt - 1.0
    # autocovariance of 1/A with unit innovations at lags 0..p-1, from its
    # impulse response (poles are held inside noise.MAX_ROOT = 0.999, where
    # the response has decayed to 1e-9 after about 20 000 samples)
    h = lfilter([1.0], nm.a, np.r_[1.0, np.zeros(32767)])
    g = np.array([float(h[:h.size - k] @ h[k:]) for k in range(p)])
    a1 = float(np.sum(nm.a))
    quad = float(np.sum(solve_toeplitz(g, np.ones(p))))
    return nm.kurt - 1.0 + 4.0 * quad / max(a1 * a1, 1e-300)


def log_se(nm, n: int) -> float:
    """Standard error of log LRV_hat for nm's model fitted to n samples."""
    return math.sqrt(log_var_rate(nm) / max(n, 1))
