# SPDX-License-Identifier: MIT
"""signals.settling: the change of a rest stretch's level in standard
errors of that change. On a stretch that is noise alone (white or AR(1))
it is a standard normal's absolute value, so its mean square is 1; a level
that really moves scores by its size in those units."""
import numpy as np
from scipy.signal import lfilter

from pneufrac_fit import signals

DRAWS = 300


def _mean_square(pole, n, rng):
    zs = []
    for _ in range(DRAWS):
        v = lfilter([1.0], [1.0, -pole], rng.normal(0.0, 1.0, n))
        zs.append(signals.settling(v))
    return float(np.mean(np.square(zs)))


def test_noise_alone_scores_a_standard_normal():
    # The mean square of DRAWS chi-square(1) draws has sd sqrt(2 / DRAWS)
    # = 0.08: within 4 of them of 1. The AR model is fitted per stretch, so
    # a little more spread with a pole; before the fix (weights 1/m in the
    # contrast) the score was m/2 too small: a mean square under 1e-4.
    rng = np.random.default_rng(11)
    for pole, n in ((0.0, 300), (0.0, 651), (0.8, 651)):
        ms = _mean_square(pole, n, rng)
        assert abs(ms - 1.0) < 4 * np.sqrt(2.0 / DRAWS) + (0.15 if pole else 0.0), (pole, n, ms)


def test_a_level_that_moves_scores_its_size():
    # White noise, sd 1, 600 samples, the level rising 1 over the stretch:
    # the thirds' means differ by 2/3; their difference's sd is
    # sqrt(2 / 200) = 0.1: about 6.7 standard errors (less the noise).
    rng = np.random.default_rng(12)
    n = 600
    v = rng.normal(0.0, 1.0, n) + np.linspace(0.0, 1.0, n)
    assert 4.0 < signals.settling(v) < 9.5
