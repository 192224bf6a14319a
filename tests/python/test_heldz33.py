# SPDX-License-Identifier: MIT
"""The held-out z under slow noise measured on a short rest stretch
(analysis-bench.md, branch heldz33). An AR model of a few hundred rest
samples of 1/f noise misses the wander slower than the stretch, so the
held-out improvement's sd under it alone is too small and z > Z95 comes
far more often than 2.5 % when neither prediction is better. guards._held_z
takes the larger of that variance and the raw noise's ARFIMA model's (of
the fit part, as guards._raw_noise makes it), which keeps the level and
still finds a large slow error removed."""
from types import SimpleNamespace

import numpy as np

from pneufrac_fit import guards, noise, sensor

N, REST, FIT_END = 6000, 300, 4500          # rest stretch, fit part, held-out block


def _slow_error():
    """Clipped troughs of a slow sine, up to 0.5 noise sd deep, less its
    mean (a held-out block less its level, as the guard takes it)."""
    x = np.sin(2 * np.pi * np.arange(N - FIT_END) / 400.0)
    m = np.minimum(x + 0.5, 0.0)
    return m - np.mean(m)


def _draws(k, rng, c0_of, c1_of):
    """k draws of 1/f noise: (z under the rest model alone, z under the
    larger of the rest model's and the raw ARFIMA model's variances)."""
    held = SimpleNamespace(held_parts=[slice(FIT_END, N)])
    rest_only, both = [], []
    for _ in range(k):
        n = sensor.coloured(N, 1.0, "pink", rng)
        nm = noise.fit([n[:REST]])
        raw = noise.fit_arfima(n[REST:FIT_END])
        c = n - np.mean(n[FIT_END:])
        c0, c1 = c.copy(), c.copy()
        c0[FIT_END:] = c0_of(c[FIT_END:])
        c1[FIT_END:] = c1_of(c[FIT_END:])
        rest_only.append(guards._held_z(held, nm, c0, c1, True))
        both.append(guards._held_z(held, nm, c0, c1, True, raw))
    return np.array(rest_only), np.array(both)


def test_held_z_keeps_its_level_when_the_rest_stretch_is_short():
    """Two predictions equally good (the same error norm): under the rest
    model alone z passes far above 2.5 % (14-20 % on five seeds of 200
    draws, review of heldz33); with the raw model's variance too it stays
    near it (1.5-7.5 %, 3.6 % pooled over 1000: somewhat liberal, as the
    raw model is fitted to a finite stretch). 300 draws: the bound 0.065
    is 2.6 binomial sd above the pooled rate."""
    u = _slow_error()
    rest_only, both = _draws(300, np.random.default_rng(11), lambda n: n + u / 2, lambda n: n - u / 2)
    assert float(np.mean(rest_only > guards.Z95)) > 0.08       # the failure this mends
    assert float(np.mean(both > guards.Z95)) < 0.065


def test_a_large_slow_error_removed_is_still_significant():
    """The reference off by a slow error up to 3 noise sd deep, the other
    prediction the noise alone: significant in nearly every draw. (The raw
    model is fitted to noise alone here; a misfit in the residual costs
    power, measured in analysis-bench.md, branch heldz33.)"""
    u = 6.0 * _slow_error()
    _, both = _draws(100, np.random.default_rng(12), lambda n: n + u, lambda n: n)
    assert float(np.mean(both > guards.Z95)) > 0.9
