# SPDX-License-Identifier: MIT
"""The paper's controllers stepped in closed loop, effects at their places.

Blocks (paper eqs. 9-16, 18, 20; pid as Remark 3 with two restricted
bellows), all as deviations from the operating point:

    x   = b/(a+b) e - a/(a+b) y                  flapper lever (eq. 15)
    x_g = play(x)                                 linkage play, if any
    p_b = k1 h(x_g)                               nozzle (eq. 9; h = x if linear)
    p_b + tau^beta D^beta p_b = pmin z + pmax tau^beta D^beta z    relay (eq. 11)
    z  held within its stops                      diaphragm at supply/exhaust
    p_c = k2 z                                    (eq. 13)
    y  = (A/ks) I^q m                             bellows (eq. 16)
    m  = p_c | r_v | p_c - r_w | r_v - r_w        p | dd | id | pid
    r + RC D^nu r = p_c                           restrictor 1/(RC s^nu + 1)

Each fractional equation is applied through integrals only: the relay as
tau^-beta I^beta p_b + p_b = pmin tau^-beta I^beta z + pmax z, a
restrictor as RC r = I^nu p_c - I^nu r (zero initial state: Caputo and
Riemann-Liouville agree, paper Remark 1). The diaphragm's stop is real:
the clipped z is what enters its own history. Every integral is affine in
the current sample (fracop.py), so the loop is one scalar equation in x per
step, solved by fixed-point iteration (its slope is the in-step loop gain,
well below 1 at 20x the data rate).

The output line (pneumatic tubing to the transmitter) follows the relay:
a transport delay of any length, then a first-order lag, both exact at the
internal rate; the delay interpolates between internal steps, so it need
not be a whole number of anything.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import lfilter

from .fracop import Integral, _hold_weights
from .nozzle import NozzleCurve

CONFIGS = ("p", "dd", "id", "pid")


@dataclass
class Effects:
    play_x: float = 0.0            # full dead-band width on x (units of x)
    play_start: float = 0.0        # where the play's follower rests: -1..1 of its half-width
    nozzle_g1: float = 0.0         # 0: linear nozzle; else g1 (units of x)
    nozzle_gap0: float = 0.0       # operating gap (units of x)
    z_lo: float = -math.inf        # diaphragm stops (deviation units of z)
    z_hi: float = math.inf
    line_delay: float = 0.0        # s
    line_lag: float = 0.0          # s


@dataclass
class Controller:
    config: str
    p: dict = field(default_factory=dict)  # paper names: a b k1 k2 A ks tau pmin pmax beta q RC nu w RCd RCi


def simulate(ctrl: Controller, fx: Effects, e: np.ndarray, h: float) -> dict:
    """Step the loop over the input deviations e (one per internal step h).

    Returns the relay output p_c before the line, the line's output, and
    the flapper displacement x (for the nozzle's visited span).
    """
    cfg, p = ctrl.config, ctrl.p
    if cfg not in CONFIGS:
        raise ValueError(f"unknown configuration {cfg}")
    ce, cy = p["b"] / (p["a"] + p["b"]), p["a"] / (p["a"] + p["b"])
    k1, k2, kA = p["k1"], p["k2"], p["A"] / p["ks"]
    pmin, pmax = p["pmin"], p["pmax"]
    cb = p["tau"] ** (-p["beta"])
    has_v = cfg in ("dd", "pid")
    has_w = cfg in ("id", "pid")
    rc_v = p["RCd"] if cfg == "pid" else p.get("RC", 0.0)
    rc_w = p["RCi"] if cfg == "pid" else p.get("RC", 0.0)

    # Operators: (order, signal index). Signals: 0 p_b, 1 z, 2 m, 3 p_c, 4 r_v, 5 r_w.
    ops = [(p["beta"], 0), (p["beta"], 1), (p["q"], 2)]
    if has_v:
        ops += [(p["nu"], 3), (p["nu"], 4)]
    if has_w:
        ops += [(p["w"], 3), (p["w"], 5)]
    integ = [Integral(a, h) for a, _ in ops]
    D = [I.D for I in integ]
    A_ = np.concatenate([I.a for I in integ])
    G0 = np.concatenate([I.g0 for I in integ])
    G1 = np.concatenate([I.g1 for I in integ])
    SIG = np.concatenate([np.full(I.n_modes, s, dtype=int) for I, (_, s) in zip(integ, ops)])
    # S (one per operator) = CMAT @ pre: each row holds its operator's mode weights
    CMAT = np.zeros((len(integ), A_.size))
    col = 0
    for i, I in enumerate(integ):
        CMAT[i, col:col + I.n_modes] = I.c
        col += I.n_modes
    X = np.zeros(A_.size)
    sig_prev = np.zeros(6)
    sig_now = np.zeros(6)

    q_zero = p["q"] == 0.0
    dz_b, dz_z = D[0], D[1]
    relay_den = pmax + pmin * cb * dz_z
    relay_num = 1.0 + cb * dz_b
    iv = 3 if has_v else None
    iw = (5 if has_v else 3) if has_w else None
    nozzle = NozzleCurve(fx.nozzle_g1, fx.nozzle_gap0) if fx.nozzle_g1 > 0 else None
    r_play = fx.play_x / 2
    play_out = -fx.play_start * r_play  # follower rests off-centre: x = 0 sits at an edge
    nonlinear = r_play > 0 or nozzle is not None or math.isfinite(fx.z_lo) or math.isfinite(fx.z_hi)

    n = e.size
    pc_out = np.empty(n)
    x_out = np.empty(n)
    x_prev = 0.0
    for k in range(n):
        pre = A_ * X + G0 * sig_prev[SIG]
        S = (CMAT @ pre).tolist()
        e_k = e[k]

        def chain(x):
            xg = x
            if r_play > 0:
                if x - play_out > r_play:
                    xg = x - r_play
                elif play_out - x > r_play:
                    xg = x + r_play
                else:
                    xg = play_out
            pb = k1 * (nozzle(xg) if nozzle is not None else xg)
            z = (relay_num * pb + cb * S[0] - pmin * cb * S[1]) / relay_den
            if z < fx.z_lo:
                z = fx.z_lo
            elif z > fx.z_hi:
                z = fx.z_hi
            pc = k2 * z
            rv = (D[iv] * pc + S[iv] - S[iv + 1]) / (rc_v + D[iv + 1]) if has_v else 0.0
            rw = (D[iw] * pc + S[iw] - S[iw + 1]) / (rc_w + D[iw + 1]) if has_w else 0.0
            if cfg == "p":
                m = pc
            elif cfg == "dd":
                m = rv
            elif cfg == "id":
                m = pc - rw
            else:
                m = rv - rw
            y = kA * (m if q_zero else D[2] * m + S[2])
            return ce * e_k - cy * y, (xg, pb, z, m, pc, rv, rw)

        if not nonlinear:  # chain is affine with a slope fixed by the D's alone
            f0, _ = chain(0.0)
            if k == 0:
                slope = chain(1.0)[0] - f0
            x = f0 / (1.0 - slope)
        else:
            x = x_prev
            for _ in range(200):
                fx_, _ = chain(x)
                if abs(fx_ - x) <= 1e-13 * (1.0 + abs(x)):
                    x = fx_
                    break
                x = fx_
        _, (xg, pb, z, m, pc, rv, rw) = chain(x)
        play_out = xg
        sig_now[:] = (pb, z, m, pc, rv, rw)
        X = pre + G1 * sig_now[SIG]
        sig_prev, sig_now = sig_now, sig_prev
        pc_out[k] = pc
        x_out[k] = x
        x_prev = x
    line = pc_out
    t = np.arange(n) * h
    if fx.line_delay > 0:
        line = np.interp(t - fx.line_delay, t, line, left=0.0)
    if fx.line_lag > 0:
        a, g0, g1 = _hold_weights(np.array([1.0 / fx.line_lag]), h)
        w = 1.0 / fx.line_lag
        line = lfilter([w * g1[0], w * g0[0]], [1.0, -a[0]], line)
    return {"pc": pc_out, "line": line, "x": x_out}
