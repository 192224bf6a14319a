# SPDX-License-Identifier: MIT
"""Do the sandwich intervals hold? A Monte Carlo of noise.sandwich on a
small regression whose truth is known, under white, AR(1), fractional
(ARFIMA) and 1/f noise: the 95 % intervals must contain the truth 95 % of
the time, within the binomial tolerance of the number of draws, and be no
wider than that needs. The noise model is the one fit.uncertainty uses
(noise.fit_arfima). (bench/bench_coverage.py measures the same on whole
diagnoses; this is the statistic alone, fast.)"""
import math

import numpy as np
from scipy.signal import fftconvolve, lfilter
from scipy.special import gammaln

from pneufrac_fit import noise

N = 4000          # samples per draw: ~200 correlation times at pole 0.9
DRAWS = 400
POLE = 0.9
# Binomial sd of a coverage estimated from DRAWS intervals at 95 %: 0.011.
# Three sd either side (a fixed seed: the test is deterministic; the band is
# what a correct statistic leaves on one run of this size, on any seed).
TOL = 3.0 * math.sqrt(0.95 * 0.05 / DRAWS)
# The median se over the estimate's rms error: 1 for a right se. The rms
# from DRAWS draws has a relative sd of 1/sqrt(2 DRAWS) = 3.5 %; 25 % is
# about 7 of them, and half the factor 1.6-1.8 that the AR model composed
# with a separately estimated d gave on fractional noise (interval29).
WIDE = 1.25
# Where the statistic's own coverage is short of 95 %, the band is centred
# on the measured coverage, 3 binomial sd of DRAWS either side (the sd at
# that coverage), so it holds on any seed. Measured, not derived:
# - 1/f noise, the slow columns: the step covers 90.8 % (10 seeds x 400
#   draws, 4000; binomial sd of that mean 0.005), the sine 93.0 %: 4.2 %
#   short (review of arfima30; docs/analysis-bench.md, branch fixarf).
ONE_OVER_F_SHORT = 0.042
# - ARFIMA(1, 0.3, 0), pole 0.5: 93.9 / 93.9 / 93.4 % (20 seeds x 400
#   draws, 8000; sd 0.003): 1.6 % short, from d's Whittle sd understating
#   d^'s spread by ~14 % (400 draws at n = 3000) where d and the pole trade
#   off (same review).
ARFIMA1_SHORT = 0.016


def _band(short: float) -> float:
    """3 binomial sd of a coverage from DRAWS draws at 95 % less `short`."""
    p = 0.95 - short
    return 3.0 * math.sqrt(p * (1.0 - p) / DRAWS)


def _ar1(rng, n):
    return lfilter([1.0], [1.0, -POLE], rng.standard_normal(n))


def _fractional(d, pole=0.0, burn=20000):
    """ARFIMA(1, d, 0) noise (pole 0: ARFIMA(0, d, 0)) by the MA(inf)
    weights psi_k = G(k+d)/(G(k+1)G(d)) of (1 - q^-1)^-d, cut after
    n + burn terms, the first burn samples dropped: another route than the
    estimator's (no periodogram, no autocovariance)."""
    def make(rng, n):
        k = np.arange(n + burn)
        psi = np.exp(gammaln(k + d) - gammaln(k + 1) - gammaln(d))
        v = fftconvolve(rng.standard_normal(n + burn), psi)[burn:n + burn]
        return lfilter([1.0], [1.0, -pole], v)
    return make


def _one_over_f(rng, n, longer=8):
    """1/f noise seen through a window of n samples of a record `longer`
    times as long (a sensor's flicker noise goes on below a record's lowest
    frequency): white noise's Fourier amplitudes scaled by f^-1/2."""
    m = longer * n
    f = np.fft.rfftfreq(m)
    g = np.r_[0.0, 1.0 / np.sqrt(f[1:])]
    v = np.fft.irfft(np.fft.rfft(rng.standard_normal(m)) * g, m)
    i = int(rng.integers(0, m - n + 1))
    return v[i:i + n]


def _draws(seed: int, make_noise=_ar1, n: int = N):
    """(estimate - truth), the sandwich's se under the noise model
    fit.uncertainty uses (noise.fit_arfima), the AR model's alone (noise.fit)
    and the white formula's, of a regression on a constant, a slow sine and
    a step, DRAWS times."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    X = np.column_stack([np.ones(n), np.sin(2 * np.pi * 3 * t / n), (t > n // 2) * 1.0])
    b = np.array([1.0, 0.5, -0.3])
    err, se, se_ar, se_white = [], [], [], []
    for _ in range(DRAWS):
        y = X @ b + make_noise(rng, n)
        bh = np.linalg.lstsq(X, y, rcond=None)[0]
        r = y - X @ bh
        err.append(bh - b)
        se.append(np.sqrt(np.diag(noise.sandwich(X, noise.fit_arfima(r)))))
        se_ar.append(np.sqrt(np.diag(noise.sandwich(X, noise.fit(r)))))
        se_white.append(np.sqrt(np.diag(np.linalg.inv(X.T @ X)) * (r @ r) / n))
    return np.array(err), np.array(se), np.array(se_ar), np.array(se_white)


def _cover(err, se):
    return np.mean(np.abs(err) <= 1.96 * se, axis=0)


def _ratio(err, se):
    """median se over the estimate's rms error, per column"""
    return np.median(se, axis=0) / np.sqrt(np.mean(err ** 2, axis=0))


def test_sandwich_intervals_hold_under_fractional_noise():
    """ARFIMA(0, 0.3, 0) and ARFIMA(1, 0.3, 0) (pole 0.5), the model family
    the sandwich assumes: coverage 95 % and the se the estimate's rms error.
    With the AR pole the coverage is 1.6 % short (ARFIMA1_SHORT: 93.4-93.9 %
    over 8000 draws; d's Whittle sd ~14 % small there), its band centred
    there (3 binomial sd of 400 draws, 0.037; 400-draw runs over seeds
    14-33 covered 90.5-96.2 %). An AR model with a d estimated after it
    (interval29) gave 88-92 % and a se 1.6-1.8x too wide: this fails there."""
    for seed, make, short in ((14, _fractional(0.3), 0.0), (15, _fractional(0.3, 0.5), ARFIMA1_SHORT)):
        err, se, se_ar, _ = _draws(seed, make, 3000)
        cover = _cover(err, se)
        assert np.all(cover >= 0.95 - short - _band(short)), (seed, cover)
        assert np.all(cover <= 0.95 + TOL), (seed, cover)
        assert np.all(np.abs(np.log(_ratio(err, se))) < math.log(WIDE)), (seed, _ratio(err, se))
        # the check has power: the AR model's intervals fall far below the band
        assert np.all(_cover(err, se_ar) < 0.95 - TOL), _cover(err, se_ar)


def test_sandwich_intervals_cover_under_one_over_f_noise():
    """Under 1/f noise the residual's AR model alone understates the power
    at the frequencies the regression's slow columns absorbed (coverage
    about 40-70 %); with the long-memory exponent the intervals nearly
    hold."""
    err, se, se_ar, _ = _draws(13, _one_over_f, 3000)
    cover = _cover(err, se)
    ratio = _ratio(err, se)
    # The sine and the step: the se their rms error, and coverage near 95 %
    # but short of it: the step 90.8 %, the sine 93.0 % over 4000 draws
    # (ONE_OVER_F_SHORT; 400-draw runs over seeds 13-22 covered the step
    # 89.2-92.2 %). 1/f power is d = 1/2, the edge of the stationary model
    # (d at its bound 0.49; a bound of 0.499 gave the same). The band below
    # is centred on the measured shortfall (3 binomial sd at that coverage,
    # 0.043); not above 95 % + the binomial band either.
    assert np.all(cover[1:] >= 0.95 - ONE_OVER_F_SHORT - _band(ONE_OVER_F_SHORT)), cover
    assert np.all(cover[1:] <= 0.95 + TOL), cover
    assert np.all(np.abs(np.log(ratio[1:])) < math.log(WIDE)), ratio
    # The constant holds too, but wider than its error (about 3x): 1/f power
    # (d = 1/2) makes the variance of a record's mean grow without bound
    # with the record's length, and this noise has power only down to the
    # frequency of a record 8 times longer. No record shows where 1/f
    # stops below its own lowest frequency, so the model extrapolates the
    # power law: the conservative side.
    assert cover[0] >= 0.95 - TOL, cover
    # the check has power: the AR model's intervals fall far below the band
    assert np.all(_cover(err, se_ar) < 0.95 - TOL), _cover(err, se_ar)


def test_sandwich_intervals_cover_under_ar1_noise():
    """AR(1) noise has no long memory: d comes out near 0, the intervals
    are nearly the AR sandwich's (no test decides whether d is used)."""
    err, se, se_ar, se_white = _draws(11)
    assert np.all(np.median(se / se_ar, axis=0) < 1.1), np.median(se / se_ar, axis=0)
    cover = _cover(err, se)
    assert np.all(np.abs(cover - 0.95) <= TOL), cover
    assert np.all(np.abs(np.log(_ratio(err, se))) < math.log(WIDE)), _ratio(err, se)
    # the check has power: the white formula's intervals (what the sandwich
    # would give if it ignored the colour) fall far outside the band
    white = _cover(err, se_white)
    assert np.all(white < 0.95 - TOL), white


def test_sandwich_intervals_cover_under_white_noise():
    """On white noise the AR order is 0, d near 0, and the sandwich is
    nearly the classical interval: coverage 95 % too, not wider."""
    rng = np.random.default_rng(12)
    n = 2000
    X = np.column_stack([np.ones(n), rng.standard_normal(n)])
    b = np.array([0.3, -1.0])
    hits = np.zeros(2)
    for _ in range(DRAWS):
        y = X @ b + rng.standard_normal(n)
        bh = np.linalg.lstsq(X, y, rcond=None)[0]
        r = y - X @ bh
        se = np.sqrt(np.diag(noise.sandwich(X, noise.fit_arfima(r))))
        hits += np.abs(bh - b) <= 1.96 * se
    cover = hits / DRAWS
    assert np.all(np.abs(cover - 0.95) <= TOL), cover


def test_d_held_at_or_above_0_on_many_slow_columns():
    """White noise fitted by 12 slow columns (a quadratic, 4 sine/cosine
    pairs, a step): the residual has lost its lowest frequencies to them,
    which reads as anti-persistence. d held >= 0 (fit_arfima) leaves the
    intervals the AR model's (median se / AR se 1.00); d free below 0
    narrows exactly these columns (0.954-0.962 per column, mean d^ -0.013,
    mean coverage 93.3 % against 94.8 %; 200 draws, branch fixarf). The
    median of 100 ratios is far inside that gap (their spread comes from
    d^, which is 0 on over half the draws)."""
    rng = np.random.default_rng(16)
    n = 3000
    t = np.arange(n)
    u = t / n
    X = np.column_stack([np.ones(n), u, u ** 2]
                        + [f(2 * np.pi * k * u) for k in (1, 2, 3, 4) for f in (np.sin, np.cos)]
                        + [(t > n // 2) * 1.0])
    ratio = []
    for _ in range(100):
        e = rng.standard_normal(n)
        r = e - X @ np.linalg.lstsq(X, e, rcond=None)[0]
        ratio.append(np.sqrt(np.diag(noise.sandwich(X, noise.fit_arfima(r)))
                             / np.diag(noise.sandwich(X, noise.fit(r)))))
    assert np.all(np.median(ratio, axis=0) >= 0.98), np.median(ratio, axis=0)


def _missed_cover(seed: int, n: int = 1000):
    """ARFIMA(1, 0.2, 0) noise, pole 0.5, on _draws' regression: the
    coverage of every column over all DRAWS draws, and over the draws
    whose d's 95 % interval includes 0, and their share."""
    rng = np.random.default_rng(seed)
    make = _fractional(0.2, 0.5)
    t = np.arange(n)
    X = np.column_stack([np.ones(n), np.sin(2 * np.pi * 3 * t / n), (t > n // 2) * 1.0])
    hit, missed = [], []
    for _ in range(DRAWS):
        e = make(rng, n)
        bh = np.linalg.lstsq(X, e, rcond=None)[0]
        nm = noise.fit_arfima(e - X @ bh)
        hit.append(np.abs(bh) <= 1.96 * np.sqrt(np.diag(noise.sandwich(X, nm))))
        missed.append(nm.d - 1.96 * nm.d_sd <= 0)
    hit, missed = np.array(hit), np.array(missed)
    return hit.mean(axis=0), hit[missed].mean(axis=0), missed.mean()


def test_long_memory_the_significance_test_misses_is_kept():
    """ARFIMA(1, 0.2, 0), pole 0.5, n = 1000: d's 95 % interval includes 0
    on 43-48 % of the records (d's sd ~0.08). d^ is used whether or not it
    is significant (no gate, fit_arfima). On those records, the mean
    coverage of the three columns: the landed model 0.82-0.89 (mean
    0.85), a gate (the AR model when the interval includes 0) 0.70-0.77
    (mean 0.72), seeds 17-22 x 400 draws (branch fixarf). The band is
    their midpoint, 0.79, clear of both ranges. Over all draws the landed
    model covers 88-94 % per column (short of 95 %: at n = 1000 d's Whittle
    sd understates d^'s spread), the gate 80-91 %."""
    _, cover, share = _missed_cover(17)
    assert 0.3 < share < 0.7, share
    assert np.mean(cover) >= 0.79, cover
