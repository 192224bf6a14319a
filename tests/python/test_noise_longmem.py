# SPDX-License-Identifier: MIT
"""The long-memory parts of noise.py: the local Whittle estimate of d, the
fractional noise's autocovariance, the fractional difference, the Toeplitz
product, and the gate that leaves records without long memory alone."""
import math

import numpy as np
from scipy.linalg import toeplitz
from scipy.signal import fftconvolve
from scipy.special import gammaln

from pneufrac_fit import noise


def _fractional_noise(rng, n, d, burn=20000):
    """(1 - q^-1)^-d eps by its MA(inf) weights psi_k = G(k+d)/(G(k+1)G(d)),
    cut after n + burn terms, the first burn samples dropped: another route
    than the estimator's (no autocovariance, no fractional difference)."""
    k = np.arange(n + burn)
    psi = np.exp(gammaln(k + d) - gammaln(k + 1) - gammaln(d))
    return fftconvolve(rng.standard_normal(n + burn), psi)[burn:n + burn]


def test_local_whittle_recovers_d():
    rng = np.random.default_rng(3)
    n = 8192
    est = []
    for _ in range(20):
        d, sd = noise.local_whittle(_fractional_noise(rng, n, 0.3), int(n ** 0.5))
        est.append(d)
    assert sd == 0.5 / math.sqrt(int(n ** 0.5))
    # the mean of 20 estimates within 3 sd of the mean of 20
    assert abs(np.mean(est) - 0.3) < 3 * sd / math.sqrt(20), np.mean(est)


def test_frac_acov_hosking():
    g = noise.frac_acov(0.3, 5)
    assert abs(g[0] - math.gamma(1 - 0.6) / math.gamma(0.7) ** 2) < 1e-12
    assert abs(g[1] / g[0] - 0.3 / 0.7) < 1e-12          # rho_1 = d / (1 - d)
    assert np.allclose(noise.frac_acov(0.0, 4), [1, 0, 0, 0])
    # the sample autocovariance of fractional noise agrees (lag 0, 1, 10)
    rng = np.random.default_rng(4)
    x = _fractional_noise(rng, 400000, 0.3, burn=40000)
    for k in (0, 1, 10):
        c = float(np.mean(x[k:] * x[:x.size - k]))
        assert abs(c - noise.frac_acov(0.3, 11)[k]) < 0.1 * noise.frac_acov(0.3, 1)[0]


def test_frac_diff_inverts():
    rng = np.random.default_rng(5)
    x = rng.standard_normal(500)
    assert np.allclose(noise.frac_diff(noise.frac_diff(x, 0.4), -0.4), x)
    assert np.allclose(noise.frac_diff(x, 1.0), np.r_[x[0], np.diff(x)])


def test_toeplitz_gram_exact():
    rng = np.random.default_rng(6)
    G = rng.standard_normal((300, 3))
    g = noise.frac_acov(0.35, 300)
    assert np.allclose(noise._toeplitz_gram(G, g), G.T @ toeplitz(g) @ G)


def test_no_long_memory_no_change():
    """White noise: d's interval includes 0 (d = 0), the sandwich is the AR
    one exactly; the estimate is recorded all the same."""
    rng = np.random.default_rng(7)
    r = rng.standard_normal(3000)
    nm = noise.fit(r)
    nl = noise.with_long_memory(nm, r)
    assert nl.d == 0.0 and nl.d_est is not None
    J = rng.standard_normal((3000, 2))
    assert np.array_equal(noise.sandwich(J, nl), noise.sandwich(J, nm))
    assert "long memory" not in nl.describe()


def test_long_memory_found_in_fractional_noise():
    rng = np.random.default_rng(8)
    r = _fractional_noise(rng, 3000, 0.4)
    nl = noise.with_long_memory(noise.fit(r), r)
    assert nl.d > 0 and "long memory" in nl.describe()
