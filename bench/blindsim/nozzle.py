# SPDX-License-Identifier: MIT
"""Flapper-nozzle back pressure from compressible flow through two orifices.

Air from the supply p_s passes a fixed orifice into the nozzle chamber
(back pressure p_b) and leaves through the curtain between nozzle and
flapper to atmosphere p_a. The curtain's conductance is proportional to the
gap g. Each orifice passes q = C p_up phi(p_dn/p_up) with the ISO 6358
form phi(r) = sqrt(1 - ((r - b)/(1 - b))^2) above the critical ratio b
(choked, phi = 1, below it). Equal flows give the gap that holds a back
pressure in closed form:

    g/g1 = p_s phi(p_b/p_s) / (p_b phi(p_a/p_b)),

g1 the gap at which both conductances are equal. The curve p_b(g) is
tabulated from it; eq. 9 is its tangent at the operating gap.

pneufrac describes the same block with the incompressible curve
F(u) = 1/(1+u^2), u = gap/x_1/2, biased at u0 = 1/sqrt(3) + bias
(docs/analysis.md, section 6; pf_effects.h). `equivalent()` states the
truth in those terms: the (x_1/2, bias) whose curve is closest, in least
squares, to this one over the displacements the record visits.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares

P_SUPPLY = 2.4   # bar absolute (1.4 bar gauge, the usual instrument supply)
P_ATM = 1.013
B_CRIT = 0.45    # measured critical ratios of small orifices sit below 0.528


def _phi(r: np.ndarray) -> np.ndarray:
    r = np.clip(r, 0.0, 1.0)
    return np.where(r <= B_CRIT, 1.0,
                    np.sqrt(np.maximum(0.0, 1.0 - ((r - B_CRIT) / (1.0 - B_CRIT)) ** 2)))


class NozzleCurve:
    """Linearised-at-gap0 nozzle: h(x) = (p_b(g0) - p_b(g0 + x))/|p_b'(g0)|.

    x and the gaps are in units of x (flapper displacement); h has unit
    slope at x = 0, so the linear model's k1 is unchanged. The gap cannot
    close below 0 (the flapper seats on the nozzle, p_b = p_s).
    """

    def __init__(self, g1: float, gap0: float):
        if g1 <= 0 or gap0 <= 0:
            raise ValueError("nozzle gaps must be positive")
        pb = P_ATM + (P_SUPPLY - P_ATM) * (1 - np.geomspace(1e-7, 1.0, 6000))[::-1]
        pb = np.concatenate(([P_ATM * (1 + 1e-9)], pb[1:-1], [P_SUPPLY]))
        pb = np.unique(np.clip(pb, P_ATM * (1 + 1e-12), P_SUPPLY))
        gap = g1 * P_SUPPLY * _phi(pb / P_SUPPLY) / (pb * _phi(P_ATM / pb))
        order = np.argsort(gap)
        self._gap = gap[order]
        self._pb = pb[order]
        self.g1, self.gap0 = g1, gap0
        dg = 1e-4 * g1
        slope = (self.pressure(gap0 + dg) - self.pressure(gap0 - dg)) / (2 * dg)
        self._p0 = self.pressure(gap0)
        self._inv_slope = 1.0 / abs(slope)

    def pressure(self, gap):
        return np.interp(np.maximum(gap, 0.0), self._gap, self._pb)

    def __call__(self, x):
        return (self._p0 - self.pressure(self.gap0 + x)) * self._inv_slope

    def equivalent(self, x_lo: float, x_hi: float) -> tuple[float, float, float]:
        """(x_1/2, bias, rms misfit over the span) of pneufrac's curve closest
        to this one on [x_lo, x_hi]."""
        xs = np.linspace(x_lo, x_hi, 401)
        target = self(xs)

        def pf_curve(xh, bias):
            u0 = 1 / math.sqrt(3) + bias
            f = lambda u: 1.0 / (1.0 + np.maximum(u, 0.0) ** 2)
            dfu0 = 2 * u0 / (1 + u0 * u0) ** 2
            return xh * (f(u0) - f(u0 + xs / xh)) / dfu0

        def res(p):
            return pf_curve(math.exp(p[0]), p[1]) - target

        best = None
        for xh0 in (0.5 * self.g1, self.g1, 2 * self.g1):
            for b0 in (-0.3, 0.0, 0.5, 1.5):
                r = least_squares(res, [math.log(xh0), b0],
                                  bounds=([-30, -0.5], [30, 10]))
                if best is None or r.cost < best.cost:
                    best = r
        rms = math.sqrt(2 * best.cost / xs.size)
        return math.exp(best.x[0]), float(best.x[1]), rms
