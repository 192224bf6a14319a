# SPDX-License-Identifier: MIT
"""Fractional integral s^-alpha as a sum of first-order modes.

For 0 < alpha < 1 (the diffusive representation of the Riemann-Liouville
integral, e.g. Montseny 1998; Yuan & Agrawal 2002):

    s^-alpha = sin(alpha pi)/pi * integral_0^inf  w^-alpha / (s + w) dw.

With w = exp(x) the integrand is smooth and decays exponentially at both
ends, so the trapezoidal rule on a uniform grid in x converges
geometrically (error about exp(-pi^2/dx) for s on the imaginary axis, whose
pole sits pi/2 from the real line). The two tails are not dropped:
modes slower than w_min act as an integrator over the record, and modes
faster than w_max as a static gain, so each becomes one extra term.
Every mode dx/dt = -w x + u is integrated exactly for u linear between two
steps (first-order hold), so the realisation is exact per mode, and the
operator's output at step n is D*u_n + S_n with S_n known before u_n: the
closed loop can then be solved at every step with no unit delay.
"""
from __future__ import annotations

import math

import numpy as np

# Quadrature band and step (rad/s, natural-log spacing). w_min = 1e-5 rad/s
# is a period of 7 days, far beyond any record; w_max = 500/h makes every
# faster mode settle within a step.
W_MIN = 1e-5
W_MAX_PER_STEP = 500.0
DX = 0.4


def _hold_weights(w: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """a, g0, g1 with x_n = a x_{n-1} + g0 u_{n-1} + g1 u_n for dx/dt = -w x + u."""
    z = w * h
    a = np.exp(-z)
    small = z < 1e-4
    zs = np.where(small, 1.0, z)
    phi1 = np.where(small, h * (1 - z / 2 + z * z / 6), h * (-np.expm1(-zs)) / zs)
    phi2 = np.where(small, h * (0.5 - z / 6 + z * z / 24),
                    h * (zs + np.expm1(-zs)) / (zs * zs))
    return a, phi1 - phi2, phi2


class Integral:
    """s^-alpha, alpha in [0, 1], realised at step h (seconds)."""

    def __init__(self, alpha: float, h: float):
        if not 0.0 <= alpha <= 1.0:
            raise ValueError(f"order {alpha} outside [0, 1]")
        self.alpha = alpha
        if alpha == 0.0:  # identity: no state
            w = np.zeros(0)
            c = np.zeros(0)
            direct = 1.0
        elif alpha == 1.0:  # plain integrator
            w = np.zeros(1)
            c = np.ones(1)
            direct = 0.0
        else:
            k = math.sin(alpha * math.pi) / math.pi
            lo, hi = math.log(W_MIN), math.log(W_MAX_PER_STEP / h)
            n = int(math.ceil((hi - lo) / DX)) + 1
            x = np.linspace(lo, hi, n)
            dx = x[1] - x[0]
            wq = np.exp(x)
            cq = k * dx * wq ** (1.0 - alpha)
            cq[0] *= 0.5
            cq[-1] *= 0.5
            # Tails: w < w_min integrates, w > w_max is static.
            w = np.concatenate(([0.0], wq))
            c = np.concatenate(([k * W_MIN ** (1.0 - alpha) / (1.0 - alpha)], cq))
            direct = k * math.exp(hi) ** (-alpha) / alpha
        self.a, g0, g1 = _hold_weights(w, h)
        self.g0 = g0
        self.c = c
        # Output = D u_n + S_n; S_n = sum c (a x_{n-1} + g0 u_{n-1}).
        self.D = float(np.sum(c * g1) + direct)
        self.g1 = g1
        self.n_modes = w.size

    def frequency_response(self, omega: np.ndarray, h: float) -> np.ndarray:
        """The discrete realisation's response at frequencies omega (rad/s)."""
        zinv = np.exp(-1j * omega * h)[:, None]
        modes = (self.g1 + self.g0 * zinv) / (1 - self.a * zinv)
        direct = self.D - float(np.sum(self.c * self.g1))
        return modes @ self.c + direct
