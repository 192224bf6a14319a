# SPDX-License-Identifier: MIT
"""What a measured signal tells about itself before any model: its noise,
its ADC steps, where the input changes, and whether the record opens at
rest. One definition of each, used by the record checks, the operating
point, the noise estimate and the evidence."""
from __future__ import annotations

import math

import numpy as np

# An input change is a step of e larger than STEP_SIGMAS times the noise on
# e (robust sd, noise_sd) and larger than rounding (1e-9 of the span).
STEP_SIGMAS = 20.0
# At rest: within REST_SIGMAS noise sd (plus one ADC step) of the opening
# level, for at least MIN_REST samples.
REST_SIGMAS = 5.0
MIN_REST = 20
MIN_LEVELS = 8             # distinct values before a grid can be an ADC's
MAD_SD = 1.482602218505602     # sd / MAD of a normal distribution


def mad_sd(x: np.ndarray) -> float:
    """Robust sd: 1.4826 x median absolute deviation."""
    x = np.asarray(x, float)
    if x.size == 0:
        return 0.0
    return MAD_SD * float(np.median(np.abs(x - np.median(x))))


def quantum(v: np.ndarray) -> float:
    """The ADC step of a signal whose values lie on a regular grid, or 0.

    The values are sorted and merged within rounding (1e-7 of the span, what
    a CSV writer's 9 significant digits leave); the smallest gap between
    levels is the candidate step. It is an ADC step when every level lies on
    its grid (within 5 % of a step), there are at least MIN_LEVELS levels,
    and they fill at least a quarter of the grid's points over the span: a
    converter's noisy signal visits most codes, while a few set levels (a
    relay, a PRBS, a staircase) are not evidence of a converter."""
    v = np.asarray(v, float)
    if v.size < 3:
        return 0.0
    u = np.unique(v)
    span = float(u[-1] - u[0])
    if u.size < MIN_LEVELS or not span > 0:
        return 0.0
    keep = np.r_[True, np.diff(u) > 1e-7 * span]
    u = u[keep]
    if u.size < MIN_LEVELS:
        return 0.0
    q = float(np.min(np.diff(u)))
    if q < 1e-6 * span or span / q > 4.0 * u.size:
        return 0.0
    k = (u - u[0]) / q
    if np.max(np.abs(k - np.round(k))) > 0.05:
        return 0.0
    return q


def noise_sd(v: np.ndarray, q: float = 0.0) -> float:
    """Robust sd of the sample-to-sample noise of a signal, from second
    differences (1.4826 MAD / sqrt 6): steps are rare outliers, and a smooth
    input (a ramp, a sine sweep) has second differences far below its
    first. A quantised signal has at least its quantisation noise q/sqrt 12."""
    v = np.asarray(v, float)
    if v.size < 3:
        return q / math.sqrt(12.0)
    d2 = v[2:] - 2.0 * v[1:-1] + v[:-2]
    return max(mad_sd(d2) / math.sqrt(6.0), q / math.sqrt(12.0))


def change_points(e: np.ndarray, sigma: float | None = None, q: float | None = None) -> np.ndarray:
    """Indices n where the input changes: |e[n] - e[n-1]| beyond STEP_SIGMAS
    times the noise on e and beyond rounding. sigma (the noise) and q (the
    ADC step) are estimated when not given."""
    e = np.asarray(e, float)
    if e.size < 2:
        return np.zeros(0, int)
    if q is None:
        q = quantum(e)
    if sigma is None:
        sigma = noise_sd(e, q)
    span = float(np.max(e) - np.min(e))
    thr = max(STEP_SIGMAS * sigma, 1e-9 * max(span, 1e-300))
    return np.flatnonzero(np.abs(np.diff(e)) > thr) + 1


def rest_length(v: np.ndarray, sigma: float, q: float) -> int:
    """Length of the opening stretch in which v stays within REST_SIGMAS
    noise sd (plus one ADC step) of its opening level (the median of the
    first 5 samples)."""
    v = np.asarray(v, float)
    if v.size == 0:
        return 0
    span = float(np.max(v) - np.min(v))
    tol = REST_SIGMAS * sigma + q + 1e-9 * max(span, 1e-300)
    level = float(np.median(v[:5]))
    out = np.flatnonzero(np.abs(v - level) > tol)
    return int(out[0]) if out.size else v.size


def first_reversal(e: np.ndarray) -> int:
    """Index of the first input change against the direction of the first
    one (the input's length if it never turns back)."""
    cp = change_points(e)
    if cp.size < 2:
        return int(np.asarray(e).size)
    d = np.sign(np.asarray(e, float)[cp] - np.asarray(e, float)[cp - 1])
    back = np.flatnonzero(d != d[0])
    return int(cp[back[0]]) if back.size else int(np.asarray(e).size)


def settling(v: np.ndarray) -> float:
    """How far v's level moves across a stretch, in standard errors: the
    mean of its last third minus that of its first third, over the sd of
    that difference under v's own noise (an AR model of v less its straight
    line, noise.fit; coloured noise wanders, and that is not settling)."""
    from . import noise
    v = np.asarray(v, float)
    n = v.size
    m = n // 3
    if m < 2:
        return 0.0
    k = np.arange(n, dtype=float)
    resid = v - np.polyval(np.polyfit(k, v, 1), k)
    # The contrast whose least-squares coefficient is the difference itself
    # (J'J = m/2, J'v = (sum of the last third - sum of the first) / 2), so
    # that the sandwich, the covariance of that coefficient, is the
    # difference's variance. With weights of 1/m it is the variance of a
    # coefficient (m/2) times the difference, and z came out m/2 too small.
    J = np.zeros((n, 1))
    J[:m, 0] = -0.5
    J[n - m:, 0] = 0.5
    var = float(noise.sandwich(J, noise.fit(resid))[0, 0])
    diff = float(np.mean(v[n - m:]) - np.mean(v[:m]))
    return abs(diff) / math.sqrt(var) if var > 0 else (0.0 if diff == 0 else math.inf)


def opening_rest(e, pc, sig_e, q_e, sig_y, q_y) -> tuple[int, str]:
    """(samples, why) of the opening stretch in which both the input and the
    output are at rest; 0 with the reason when there is none. The input
    stays within REST_SIGMAS of its sample-to-sample noise; the output must
    not be settling (a controller still moving, or an integrator still
    running, is not at an operating point): its level may not change across
    the stretch by more than REST_SIGMAS standard errors of its own noise,
    coloured or not."""
    k = rest_length(e, sig_e, q_e)
    if k < MIN_REST:
        return 0, (f"the input moves within the first {MIN_REST} samples" if k < len(e)
                   else "the input never moves")
    z = settling(pc[:k])
    if z > REST_SIGMAS:
        return 0, (f"the output is still settling while the input rests (its level moves "
                   f"{z:.1f} standard errors)")
    return k, ""
