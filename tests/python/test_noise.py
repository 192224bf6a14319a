# SPDX-License-Identifier: MIT
"""The residual's noise model (noise.py): AR order and coefficients,
whitening, and intervals that hold under coloured noise."""
import numpy as np
import pytest
from scipy.signal import lfilter

from pneufrac_fit import noise


def test_white_noise_gets_order_zero():
    nm = noise.fit(np.random.default_rng(0).standard_normal(20000))
    assert nm.order == 0 and nm.colour_factor() == pytest.approx(1.0)


def test_ar1_is_recovered():
    w = np.random.default_rng(1).standard_normal(50000)
    v = lfilter([1.0], [1.0, -0.9], w)
    nm = noise.fit(v)
    assert nm.order >= 1 and nm.a[1] == pytest.approx(-0.9, abs=0.02)
    assert nm.sigma2 == pytest.approx(1.0, rel=0.05)
    assert np.std(nm.whiten(v)) == pytest.approx(1.0, rel=0.05)


def test_random_walk_is_kept_stable():
    v = np.cumsum(np.random.default_rng(2).standard_normal(20000))
    nm = noise.fit(v)
    assert np.max(np.abs(np.roots(nm.a))) <= noise.MAX_ROOT + 1e-9


def test_sandwich_interval_covers_under_coloured_noise():
    """The mean of AR(1) noise: the white formula is ~4x too narrow at pole
    0.9; the sandwich gets the theory's sd(1/(1 - phi))/sqrt(n)."""
    n = 40000
    v = lfilter([1.0], [1.0, -0.9], np.random.default_rng(3).standard_normal(n))
    J = np.ones((n, 1))
    se = float(np.sqrt(noise.sandwich(J, noise.fit(v))[0, 0]))
    theory = 1.0 / (1 - 0.9) / np.sqrt(n)
    white = float(np.std(v)) / np.sqrt(n)
    assert se == pytest.approx(theory, rel=0.15)
    assert se > 3 * white


def test_undetermined_direction_has_infinite_variance():
    J = np.column_stack([np.ones(100), np.ones(100)])
    cov = noise.sandwich(J, noise.white(1.0, 100))
    assert np.isinf(cov[0, 0]) and np.isinf(cov[1, 1])
