# SPDX-License-Identifier: MIT
"""The rest model's long-run variance judged by its sampling error
(guards.noise_for, longrun.py; docs/analysis-bench.md, branch noise30)."""
import math
from types import SimpleNamespace

import numpy as np
from scipy.signal import lfilter

from pneufrac_fit import guards, longrun, noise


def _ar1(rng, phi, n):
    return lfilter([1.0], [1.0, -phi], rng.standard_normal(n + 3000))[3000:]


def _less_slow_directions(r):
    """r less its offset, trend and three slow exponentials (200, 1000 and
    3000 samples) by least squares: a stand-in for what a model's fit
    absorbs of the noise (gains, offsets, slow time constants), which
    lowers the residual's slow power below the noise's."""
    t = np.arange(r.size, dtype=float)
    A = np.column_stack([np.ones_like(t), t] + [np.exp(-t / s) for s in (200.0, 1000.0, 3000.0)])
    return r - A @ np.linalg.lstsq(A, r, rcond=None)[0]


def _stub(nm):
    """A problem whose one fit part is the whole record, the rest stretch
    nm was measured on its first nm.n samples (as diagnose does)."""
    return SimpleNamespace(nm=nm, fit_pieces=lambda r, start=0: [r[start:]])


def test_the_log_lrv_se_is_the_delta_methods():
    """AR(1) of pole phi: n Var(log LRV) = 2 + 4 (1 - phi^2) / (1 - phi)^2
    (Var(log sigma2) = 2/n; Var(phi) = (1 - phi^2)/n; d log LRV / d phi =
    2 / (1 - phi)); white noise: 2."""
    for phi in (0.5, 0.9, 0.99):
        nm = noise.NoiseModel(np.array([1.0, -phi]), 1.0, 1.0, 1000)
        want = 2.0 + 4.0 * (1.0 - phi * phi) / (1.0 - phi) ** 2
        assert math.isclose(longrun.log_var_rate(nm), want, rel_tol=1e-6)
    assert longrun.log_var_rate(noise.white(1.0, 100)) == 2.0
    assert math.isclose(longrun.log_se(noise.white(1.0, 100), 200), 0.1)


def test_the_se_matches_the_spread_of_fitted_models():
    """Where the asymptotics hold (a moderate pole on 2000 samples, and a
    resonant AR(2)), the se from a fitted model is the sd of log LRV over
    draws, within 15 %."""
    rng = np.random.default_rng(31)
    for den in ([1.0, -0.7], [1.0, -2 * 0.9 * math.cos(0.4), 0.81]):
        logs, ses = [], []
        for _ in range(200):
            x = lfilter([1.0], den, rng.standard_normal(4000))[2000:]
            nm = noise.fit(x)
            logs.append(math.log(longrun.variance(nm)))
            ses.append(longrun.log_se(nm, nm.n))
        assert abs(np.std(logs) / np.median(ses) - 1.0) < 0.15


def test_true_slow_noise_at_rest_fires_within_the_level():
    """The rest stretch the noise alone (AR(1) of pole 0.99, 650 samples),
    the residual the same noise over 6000 samples less the slow directions
    a fit absorbs: the rule may fire at its level, 0.1 % (1 expected in
    1000 draws; 5 or more has probability 0.004). The 4x ratio it replaced
    fired on 14 of these 1000 draws; this rule's largest z was 1.6. A
    moderate pole (0.5, 300 samples at rest) is where the level shows: the
    5 % point fires there about 50 times in 1000."""
    rng = np.random.default_rng(30)
    for phi, n_rest, n in ((0.99, 650, 6000), (0.5, 300, 3000)):
        fired = 0
        for _ in range(1000):
            x = _ar1(rng, phi, n_rest + n)
            rest = noise.fit(x[:n_rest])
            fired += guards.noise_for(_stub(rest), _less_slow_directions(x)) is not rest
        assert fired <= 4, (phi, fired)


def test_heavy_tailed_noise_at_rest_fires_within_the_level():
    """t(3) innovations (kurtosis far above 3; a spike-prone sensor): the
    innovation variance's sampling error is (kappa - 1)/n, not 2/n; with the
    Gaussian se the rule fired on 1-8 % of such draws (the review)."""
    rng = np.random.default_rng(33)
    fired = 0
    for _ in range(400):
        x = lfilter([1.0], [1.0, -0.5], rng.standard_t(3, 3300))
        rest = noise.fit(x[:300])
        fired += guards.noise_for(_stub(rest), x - np.mean(x)) is not rest
    assert fired <= 3


def test_a_settling_rest_stretch_like_blind_seed_5s_is_caught():
    """White noise whose 651-sample rest stretch opens 4.7 sd below its
    level and settles with time constant 150 samples (blind seed 5's
    two-lag-backlash-dd), or 5 sd with 20 samples: the rest model's slow
    noise is significantly above the residual's, every draw. The residual
    holds the settling too (a model is flat over a rest stretch), as in
    diagnose; a slow settling (500 samples) is the case a residual model
    fitted over the rest stretch hid (2 of 40 draws caught, the review)."""
    rng = np.random.default_rng(32)
    k = np.arange(651)
    for amplitude, tau in ((4.7, 150.0), (5.0, 20.0), (4.7, 500.0), (20.0, 300.0)):
        for _ in range(10):
            opening = rng.standard_normal(651) - amplitude * np.exp(-k / tau)
            rest = noise.fit(opening)
            r1 = np.r_[opening, rng.standard_normal(14_000)]
            assert guards.noise_for(_stub(rest), r1) is not rest, (amplitude, tau)
