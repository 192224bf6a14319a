# SPDX-License-Identifier: MIT
"""Balanced realisation of a stable discrete system and its reduction to r
states, by the square-root method (Laub et al. 1987; Tombs and Postlethwaite
1987): Gramians from scipy's discrete Lyapunov solver, factors and the SVD
from numpy, no linear algebra written here.

- truncation keeps the r states with the largest Hankel singular values;
  its error is largest at high frequency and it keeps the high-frequency
  gain;
- residualisation (singular perturbation: Fernando and Nicholson 1982, Liu
  and Anderson 1989) sets the discarded states to their steady state
  instead, so the DC gain is kept exactly; its error is largest at high
  frequency, where a controller's response is settled within a few samples.
Both have the bound |G - G_r|_inf <= 2 sum of the discarded Hankel singular
values; the reduction rule itself (pneufrac_reduce.reduce) measures the
step response instead.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg as sl

METHODS = ("residualise", "truncate")
# Hankel singular values below this fraction of the largest are numerical
# rank deficiency (a state the input cannot reach or the output cannot
# see), not dynamics: the balanced realisation leaves them out.
RANK_TOL = 1e-13


class NotStable(ValueError):
    """A pole on or outside the unit circle: no Gramians."""


def _factor(x: np.ndarray) -> np.ndarray:
    """L with x = L L^T for a symmetric positive semidefinite x (rounding
    may leave tiny negative eigenvalues, which are zero)."""
    w, v = np.linalg.eigh((x + x.T) / 2)
    return v * np.sqrt(np.clip(w, 0.0, None))


class Balanced:
    """The minimal balanced realisation of (A, B, C, D), single input and
    output; .hsv are its Hankel singular values, largest first."""

    def __init__(self, a, b, c, d):
        a, b, c = (np.asarray(x, dtype=float) for x in (a, b, c))
        radius = np.max(np.abs(np.linalg.eigvals(a))) if a.size else 0.0
        if not radius < 1.0:
            raise NotStable(f"a pole at |z| = {radius:.17g}")
        # A diagonal similarity by powers of two (exact) first: the runtime's
        # states span many decades.
        a, t = sl.matrix_balance(a, permute=False)
        s = np.diag(t)
        b, c = b / s[:, None], c * s[None, :]
        p = sl.solve_discrete_lyapunov(a, b @ b.T)
        q = sl.solve_discrete_lyapunov(a.T, c.T @ c)
        lc, lo = _factor(p), _factor(q)
        u, hsv, vt = np.linalg.svd(lo.T @ lc)
        m = int(np.sum(hsv > hsv[0] * RANK_TOL)) if hsv.size and hsv[0] > 0 else 0
        k = 1.0 / np.sqrt(hsv[:m])
        t, ti = lc @ vt[:m].T * k, (u[:, :m] * k).T @ lo.T
        self.a, self.b, self.c = ti @ a @ t, ti @ b, c @ t
        self.d = np.asarray(d, dtype=float).reshape(1, 1)
        self.hsv = hsv[:m]

    @property
    def order(self) -> int:
        return len(self.hsv)

    def reduce(self, r: int, method: str = "residualise"):
        """(A_r, B_r, C_r, D_r) with r states (1 <= r <= order)."""
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}")
        if not 1 <= r <= self.order:
            raise ValueError(f"order {r} outside 1..{self.order}")
        a, b, c, d = self.a, self.b, self.c, self.d
        if method == "truncate" or r == self.order:
            return a[:r, :r], b[:r], c[:, :r], d.copy()
        # x2 at its steady state: x2 = (I - A22)^-1 (A21 x1 + B2 u)
        m = np.linalg.solve(np.eye(self.order - r) - a[r:, r:], np.hstack([a[r:, :r], b[r:]]))
        return (a[:r, :r] + a[:r, r:] @ m[:, :r], b[:r] + a[:r, r:] @ m[:, r:],
                c[:, :r] + c[:, r:] @ m[:, :r], d + c[:, r:] @ m[:, r:])
