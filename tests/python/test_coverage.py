# SPDX-License-Identifier: MIT
"""Do the sandwich intervals hold? A Monte Carlo of noise.sandwich on a
small regression whose truth is known, under AR(1) noise: the 95 %
intervals must contain the truth 95 % of the time, within the binomial
tolerance of the number of draws. (bench/bench_coverage.py measures the
same on whole diagnoses; this is the statistic alone, fast.)"""
import math

import numpy as np
from scipy.signal import lfilter

from pneufrac_fit import noise

N = 4000          # samples per draw: ~200 correlation times at pole 0.9
DRAWS = 400
POLE = 0.9
# Binomial sd of a coverage estimated from DRAWS intervals at 95 %: 0.011.
# Three sd either side (a fixed seed: the test is deterministic; the band is
# what a correct statistic leaves on one run of this size). The sandwich's
# own finite-sample bias (the AR coefficient estimated from a residual: at
# N = 4000 about 1 % of coverage) lies inside it.
TOL = 3.0 * math.sqrt(0.95 * 0.05 / DRAWS)


def _draws(seed: int):
    """(estimate - truth) and the sandwich's and the white formula's se of
    a regression on a constant, a slow sine and a step, DRAWS times."""
    rng = np.random.default_rng(seed)
    t = np.arange(N)
    X = np.column_stack([np.ones(N), np.sin(2 * np.pi * 3 * t / N), (t > N // 2) * 1.0])
    b = np.array([1.0, 0.5, -0.3])
    err, se, se_white = [], [], []
    for _ in range(DRAWS):
        y = X @ b + lfilter([1.0], [1.0, -POLE], rng.standard_normal(N))
        bh = np.linalg.lstsq(X, y, rcond=None)[0]
        r = y - X @ bh
        err.append(bh - b)
        se.append(np.sqrt(np.diag(noise.sandwich(X, noise.fit(r)))))
        se_white.append(np.sqrt(np.diag(np.linalg.inv(X.T @ X)) * (r @ r) / N))
    return np.array(err), np.array(se), np.array(se_white)


def test_sandwich_intervals_cover_under_ar1_noise():
    err, se, se_white = _draws(11)
    cover = np.mean(np.abs(err) <= 1.96 * se, axis=0)
    assert np.all(np.abs(cover - 0.95) <= TOL), cover
    # the check has power: the white formula's intervals (what the sandwich
    # would give if it ignored the colour) fall far outside the band
    white = np.mean(np.abs(err) <= 1.96 * se_white, axis=0)
    assert np.all(white < 0.95 - TOL), white


def test_sandwich_intervals_cover_under_white_noise():
    """On white noise the AR order is 0 and the sandwich is the classical
    interval: coverage 95 % too, not wider."""
    rng = np.random.default_rng(12)
    n = 2000
    X = np.column_stack([np.ones(n), rng.standard_normal(n)])
    b = np.array([0.3, -1.0])
    hits = np.zeros(2)
    for _ in range(DRAWS):
        y = X @ b + rng.standard_normal(n)
        bh = np.linalg.lstsq(X, y, rcond=None)[0]
        se = np.sqrt(np.diag(noise.sandwich(X, noise.fit(y - X @ bh))))
        hits += np.abs(bh - b) <= 1.96 * se
    cover = hits / DRAWS
    assert np.all(np.abs(cover - 0.95) <= TOL), cover
