# SPDX-License-Identifier: MIT
"""Run a controller on an input sampled at the internal rate.

Linear controllers go through an exact block recursion (no per-sample
Python loop). With an effect inside the loop (backlash, nozzle,
saturation) the loop is opened at the effects: each internal sample the
linear part is affine in the effects' outputs v, w = s + J v, and
v = N(w) is solved by fixed-point iteration, a contraction because J (the
in-sample loop gain through the relay's feedthrough and the bellows) times
the effects' slopes has a spectral radius well below one; this is checked,
not assumed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import controller
from .discretise import Discrete, foh
from .effects import Effects, delay, nozzle, nozzle_max_slope, play

BLOCK = 256          # samples per block of the linear recursion
CONTRACTION_MAX = 0.5


@dataclass
class Run:
    x: np.ndarray     # flapper displacement (deviation, units of x)
    pc: np.ndarray    # relay output before the clip (deviation)
    line: np.ndarray  # output line, after lag and dead time (deviation)


def design(config: str, p: dict, fx: Effects, fs_int: float, duration: float) -> Discrete:
    band = controller.band_for(fs_int, duration)
    ss = controller.build(config, p, band, lag=fx.lag,
                          open_x=fx.deadband > 0 or fx.nozzle_xh > 0, open_pc=fx.saturates(),
                          wind=fx.sat_wind)
    return foh(ss, 1.0 / fs_int)


def _linear(d: Discrete, u: np.ndarray) -> np.ndarray:
    """Outputs (n, p) of x[n+1] = Phi x + G0 u[n] + G1 u[n+1] from x[0] = 0,
    for one input. With z = x - G1 u it is a standard recursion
    z[n+1] = Phi z + (Phi G1 + G0) u[n], y = C z + (C G1 + D) u, run in
    blocks of K samples: y_block = O z0 + T u_block, z_next = Phi^K z0 + R u_block."""
    A = d.Phi
    B = (d.Phi @ d.G1 + d.G0)[:, 0]
    C = d.C
    D = (d.C @ d.G1 + d.D)[:, 0]
    n, N, p, K = u.size, A.shape[0], C.shape[0], BLOCK
    O = np.empty((K, p, N))
    AkB = np.empty((K, N))      # A^k B
    M = np.eye(N)
    v = B.copy()
    for k in range(K):
        O[k] = C @ M
        AkB[k] = v
        M = A @ M
        v = A @ v
    AK = M
    h = np.empty((K, p))        # Markov parameters
    h[0] = D
    h[1:] = AkB[:K - 1] @ C.T
    T = np.zeros((p, K, K))
    for k in range(K):
        T[:, k:, k] = h[:K - k].T
    R = AkB[::-1].T             # N x K: column j is A^(K-1-j) B
    nb = -(-n // K)
    U = np.zeros(nb * K)
    U[:n] = u
    U = U.reshape(nb, K)
    RU = U @ R.T                # nb x N
    Z = np.empty((nb, N))
    z = -d.G1[:, 0] * u[0]      # x[0] = 0
    for j in range(nb):
        Z[j] = z
        z = AK @ z + RU[j]
    Y = np.einsum("kpn,jn->jkp", O, Z) + np.einsum("pkl,jl->jkp", T, U)
    return Y.reshape(nb * K, p)[:n]


def _with_effects(d: Discrete, e: np.ndarray, fx: Effects, p: dict, pc0: float) -> np.ndarray:
    ce, _ = controller.lever(p)
    has_x = fx.deadband > 0 or fx.nozzle_xh > 0
    has_pc = fx.saturates()
    r = fx.deadband * ce / 2.0
    xh = fx.nozzle_xh * ce
    lo, hi = fx.sat_lo - pc0, fx.sat_hi - pc0
    if has_pc and not lo < 0.0 < hi:
        raise ValueError("operating point outside the saturation limits")
    xf_rest = fx.backlash_side * r      # the play rests at an edge or between
    state = {"xb": xf_rest}

    def n_x(x: float) -> float:
        xb = play(state["xb"], x, r) if r > 0 else x
        return (nozzle(xb - xf_rest, xh, fx.nozzle_u0) if xh > 0 else xb - xf_rest), xb

    nv = 1 + has_x + has_pc
    iv = list(range(1, nv))
    wrows = ([0] if has_x else []) + ([1] if has_pc else [])
    slope = [nozzle_max_slope(fx.nozzle_u0) if xh > 0 else 1.0] * has_x + [1.0] * has_pc
    J0 = d.D[np.ix_(wrows, iv)]
    J1 = d.C[wrows] @ d.G1[:, iv] + J0
    for J in (J0, J1):
        # |J| diag(slope) is non-negative: its Perron root below one makes the
        # iteration a contraction in a weighted max-norm.
        if np.max(np.abs(np.linalg.eigvals(np.abs(J) * np.asarray(slope)))) >= CONTRACTION_MAX:
            raise ValueError("in-sample loop gain through the effects too high")
    Cw, Dwe = d.C[wrows], d.D[wrows, 0]
    G1e, G1v = d.G1[:, 0], d.G1[:, iv]
    n = e.size
    out = np.empty((n, 3))
    x = np.zeros(d.Phi.shape[0])
    u_prev = np.zeros(nv)
    J = J0
    for k in range(n):
        if k:
            xs = d.Phi @ x + d.G0 @ u_prev + G1e * e[k]
        else:
            xs = x
        s = Cw @ xs + Dwe * e[k]
        w = s.copy()
        for _ in range(100):
            v = []
            if has_x:
                vx, xb = n_x(w[0])
                v.append(vx)
            if has_pc:
                v.append(min(max(w[-1], lo), hi))
            w_new = s + J @ v
            done = np.max(np.abs(w_new - w)) <= 1e-12 * (1.0 + np.max(np.abs(w)))
            w = w_new
            if done:
                break
        else:
            raise RuntimeError("in-loop effect iteration did not converge")
        v = []
        if has_x:
            vx, state["xb"] = n_x(w[0])
            v.append(vx)
        if has_pc:
            v.append(min(max(w[-1], lo), hi))
        v = np.asarray(v)
        x = xs + (G1v @ v if k else 0.0)
        u = np.concatenate(([e[k]], v))
        out[k] = d.C @ x + d.D @ u
        u_prev = u
        J = J1
    return out


def run(config: str, p: dict, fx: Effects, e: np.ndarray, fs_int: float,
        pc0: float = 0.0, duration: float | None = None) -> Run:
    """e: input deviation at the internal rate, starting at t = 0 from rest
    (the state is at rest at t = 0; a non-zero e[0] is a step at t = 0)."""
    e = np.asarray(e, dtype=float)
    if duration is None:
        duration = e.size / fs_int
    d = design(config, p, fx, fs_int, duration)
    y = _with_effects(d, e, fx, p, pc0) if fx.in_loop() else _linear(d, e)
    line = delay(y[:, 2], fs_int, fx.dead_time)
    return Run(y[:, 0], y[:, 1], line)
