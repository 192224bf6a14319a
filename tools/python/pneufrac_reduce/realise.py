# SPDX-License-Identifier: MIT
"""A reduced system in the form the bank runtime runs (lib pf_bank.h), in
double: its modes, decoupled.

Canonical form (physical units, output gain 1 per mode):
    y = D u + sum_k s_k + sum_j eta_j,1
    real mode k:  s_k <- s_k + lam_k (beta_k u - s_k)       (beta_k: its DC gain)
    pair j:       eta_j <- eta_j + L_j (beta_j u - eta_j),   L_j = [[alpha, omega], [-omega, alpha]]
lam_k = 1 - z_k and 1 - alpha -+ j omega = z_j are the poles' distances
from z = 1, the numbers that set each mode's time scale. A pair's state is
rotated so that only its first component reaches the output (any rotation
commutes with L_j), and scaled so that its output gain is 1.

pneufrac_reduce.fixed normalises this form for the runtimes (state bounds,
power-of-two output gains) and quantises it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sl
import scipy.signal as sg

# The runtimes hold a distance from z = 1 in [2^-30, 2) (a 16-bit mantissa
# with a shift into 32 fraction bits: pf_bank.h); beyond 1.99 (a pole near
# z = -1) a section's rounding bias would grow as 1/(2 - lam).
LAM_MIN, LAM_MAX = 2.0 ** -30, 1.99
# Modal coordinates whose condition number exceeds this cancel too much
# between modes to be worth realising (nearly repeated poles).
MAX_COND = 1e8


class NotRealisable(ValueError):
    """The reduced system has no bank form the runtimes can hold."""


@dataclass
class Bank:
    fs: float
    d: float
    lam: np.ndarray = field(default_factory=lambda: np.zeros(0))    # real modes
    beta: np.ndarray = field(default_factory=lambda: np.zeros(0))
    alpha: np.ndarray = field(default_factory=lambda: np.zeros(0))  # pairs
    omega: np.ndarray = field(default_factory=lambda: np.zeros(0))
    beta_pair: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    delay_len: int = 0

    @property
    def order(self) -> int:
        return len(self.lam) + 2 * len(self.alpha)

    def pair_input(self) -> np.ndarray:
        """b_j = L_j beta_j: each pair's input vector (as x' = M x + b u)."""
        a, w, bt = self.alpha, self.omega, self.beta_pair
        return np.stack([a * bt[:, 0] + w * bt[:, 1], -w * bt[:, 0] + a * bt[:, 1]], axis=1)

    def poles(self) -> np.ndarray:
        return np.concatenate([1.0 - self.lam, 1.0 - self.alpha + 1j * self.omega,
                               1.0 - self.alpha - 1j * self.omega])

    def step(self, n: np.ndarray) -> np.ndarray:
        """Unit-step response at samples n >= 0 from rest (closed form),
        without the dead time."""
        ni = np.asarray(n, dtype=np.int64)[:, None]
        y = np.full(ni.shape[0], self.d)
        if len(self.lam):
            slow = self.lam <= 1.0
            rise = np.empty((ni.shape[0], len(self.lam)))
            # 1 - (1 - lam)^n; expm1 and log1p keep its digits for lam near 0
            rise[:, slow] = -np.expm1(ni * np.log1p(-self.lam[slow]))
            rise[:, ~slow] = 1.0 - (1.0 - self.lam[~slow]) ** ni
            y += (self.beta * rise).sum(axis=1)
        if len(self.alpha):
            z = 1.0 - self.alpha + 1j * self.omega
            b = self.pair_input() @ np.array([1.0, 1j])
            y += np.real(b * (1.0 - z ** ni) / (self.alpha - 1j * self.omega)).sum(axis=1)
        return y

    def run(self, u: np.ndarray) -> np.ndarray:
        """Output for input u from rest, in double (scipy's lfilter per
        mode), with the dead time: the reference a fixed-point run is
        measured against."""
        u = np.asarray(u, dtype=float)
        y = self.d * u
        for lam, beta in zip(self.lam, self.beta):
            y += sg.lfilter([0.0, lam * beta], [1.0, lam - 1.0], u)
        if len(self.alpha):
            # eta_1 + j eta_2 follows one complex first-order recursion
            z = 1.0 - self.alpha + 1j * self.omega
            for zj, bj in zip(z, self.pair_input() @ np.array([1.0, 1j])):
                y += np.real(sg.lfilter([0.0, bj], [1.0, -zj], u.astype(complex)))
        if self.delay_len:
            y = np.concatenate([np.zeros(self.delay_len), y])[:len(u)]
        return y


def realise(a, b, c, d, fs: float) -> Bank:
    """The bank form of (A, B, C, D); NotRealisable if a pole lies outside
    what the runtimes hold or the modes nearly coincide."""
    a = np.asarray(a, dtype=float)
    z, v = np.linalg.eig(a)
    cond = np.linalg.cond(v)
    if not cond < MAX_COND:
        raise NotRealisable(f"nearly repeated poles (modal condition number {cond:.2g})")
    wr, vr = sl.cdf2rdf(z, v)
    bm = np.linalg.solve(vr, np.asarray(b, dtype=float)).ravel()
    cm = (np.asarray(c, dtype=float) @ vr).ravel()
    out = Bank(fs=float(fs), d=float(np.asarray(d).ravel()[0]))
    lam, beta, alpha, omega, bpair = [], [], [], [], []
    i = 0
    while i < len(z):
        if i + 1 < len(z) and wr[i, i + 1] != 0.0:      # a 2 x 2 block
            m = wr[i:i + 2, i:i + 2]
            bx, cx = bm[i:i + 2].copy(), cm[i:i + 2].copy()
            if m[0, 1] > 0.0:                            # make it [[a, -w], [w, a]]
                bx[1], cx[1] = -bx[1], -cx[1]
            al, om = 1.0 - m[0, 0], abs(m[0, 1])
            g = np.hypot(cx[0], cx[1])
            if g > 0.0:
                cs, sn = cx / g
                # eta = g R^T xi: output eta_1, input g R^T b
                bb = g * np.array([cs * bx[0] + sn * bx[1], -sn * bx[0] + cs * bx[1]])
                det = al * al + om * om
                alpha.append(al)
                omega.append(om)
                bpair.append([(al * bb[0] - om * bb[1]) / det, (om * bb[0] + al * bb[1]) / det])
            i += 2
        else:
            la = 1.0 - wr[i, i]
            if cm[i] * bm[i] != 0.0:
                lam.append(la)
                beta.append(cm[i] * bm[i] / la)
            i += 1
    # slowest first: the order of the runtime's sections, and of the header
    k, j = np.argsort(lam, kind="stable"), np.argsort(alpha, kind="stable")
    out.lam, out.beta = np.array(lam)[k], np.array(beta)[k]
    out.alpha, out.omega = np.array(alpha)[j], np.array(omega)[j]
    out.beta_pair = np.array(bpair).reshape(-1, 2)[j]
    for name, v in (("a real pole's 1 - z", out.lam), ("a pair's 1 - Re z", out.alpha),
                    ("a pair's Im z", out.omega)):
        bad = v[(v < LAM_MIN) | (v > LAM_MAX)]
        if len(bad):
            raise NotRealisable(f"{name} = {bad[0]:.3g} is outside [2^-30, {LAM_MAX}] "
                                "(a pole too close to z = 1 or to z = -1)")
    if len(out.alpha) and np.any((1 - out.alpha) ** 2 + out.omega ** 2 >= 1.0):
        raise NotRealisable("an unstable complex pole pair")
    return out
