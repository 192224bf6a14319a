# SPDX-License-Identifier: MIT
"""Rational approximation of the fractional integrator s^-alpha by
quadrature of its diffusive (Stieltjes) representation.

For 0 < alpha < 1 (e.g. Montseny, "Diffusive representation of
pseudo-differential time-operators", ESAIM Proc. 5, 1998):

    s^-alpha = sin(alpha pi)/pi * integral_0^inf xi^-alpha / (s + xi) dxi .

With xi = exp(theta) the integrand is exp(theta (1-alpha)) / (s + exp(theta)),
analytic in a strip of half-width pi/2 around the real theta axis for s on
the imaginary axis, so the trapezoidal rule on a uniform theta grid with
step h converges like exp(-pi^2 / h) (Trefethen & Weideman, SIAM Review
56(3), 2014). The two truncated tails are each folded into one extra pole
whose first two asymptotic terms match the tail's:

    low tail  (|s| >> xi_min): c/s - c xi_lo / s^2,
    high tail (|s| << xi_max): D0 - D1 s.

The result is strictly proper, sum_k c_k / (s + xi_k), a diagonal state
space with real poles. This is deliberately unlike the library's
Oustaloup zero/pole placement: the poles and weights come from a quadrature
rule, not from a frequency-domain fit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

NODES_PER_DECADE = 4  # h = ln(10)/4 = 0.58: quadrature error ~ exp(-pi^2/h) ~ 4e-8


@dataclass(frozen=True)
class Modes:
    """s^-alpha ~ gain + sum c_k / (s + xi_k): poles -xi (rad/s), weights c."""
    xi: np.ndarray
    c: np.ndarray
    gain: float  # direct term: only alpha = 0 (a static spring) has one


def frac_integrator(alpha: float, xi_min: float, xi_max: float,
                    nodes_per_decade: int = NODES_PER_DECADE) -> Modes:
    """Modes of s^-alpha, accurate for xi_min << |s| << xi_max."""
    if not 0.0 <= alpha <= 1.0 or not math.isfinite(alpha):
        raise ValueError(f"order {alpha} outside [0, 1]")
    if not 0.0 < xi_min < xi_max:
        raise ValueError("need 0 < xi_min < xi_max")
    if alpha == 0.0:
        return Modes(np.zeros(0), np.zeros(0), 1.0)
    if alpha == 1.0:
        return Modes(np.zeros(1), np.ones(1), 0.0)
    th_lo, th_hi = math.log(xi_min), math.log(xi_max)
    n = max(2, int(math.ceil((th_hi - th_lo) / math.log(10.0) * nodes_per_decade)))
    theta = np.linspace(th_lo, th_hi, n + 1)
    h = theta[1] - theta[0]
    w = np.full(n + 1, h)
    w[0] = w[-1] = h / 2.0
    xi = np.exp(theta)
    c = w * np.exp(theta * (1.0 - alpha))
    a = alpha
    # Tails, plus the Euler-Maclaurin end correction -h^2/12 [f'(b) - f'(a)]
    # of the trapezoidal rule on a truncated interval (its O(h^2) error;
    # what remains is O(h^4)), each expanded to two terms in s.
    e_lo, e_hi = math.exp(th_lo), math.exp(th_hi)
    t0 = e_lo ** (1.0 - a) * (1.0 / (1.0 - a) + h * h * (1.0 - a) / 12.0)
    t1 = e_lo ** (2.0 - a) * (1.0 / (2.0 - a) + h * h * (2.0 - a) / 12.0)
    c_lo, xi_lo = t0, t1 / t0
    d0 = e_hi ** (-a) * (1.0 / a + h * h * a / 12.0)
    d1 = e_hi ** (-1.0 - a) * (1.0 / (1.0 + a) + h * h * (1.0 + a) / 12.0)
    xi_hi = d0 / d1
    c_hi = d0 * xi_hi
    k = math.sin(a * math.pi) / math.pi
    xi = np.concatenate(([xi_lo], xi, [xi_hi]))
    c = k * np.concatenate(([c_lo], c, [c_hi]))
    return Modes(xi, c, 0.0)


def response(m: Modes, s: np.ndarray) -> np.ndarray:
    """The approximation's transfer function at complex s."""
    s = np.asarray(s, dtype=complex)
    return m.gain + (m.c[None, :] / (s[..., None] + m.xi[None, :])).sum(axis=-1)
