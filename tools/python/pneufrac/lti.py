# SPDX-License-Identifier: MIT
"""The realised controller as a linear system in scipy's conventions:
state space, zeros/poles/gain and second-order sections.

The state space is the library's (pf_ctrl_state_space: the runtime read
off step by step, so it is the arithmetic that runs). The zeros and poles
are eigenvalues (LAPACK's dgeev through numpy, as `pneufrac design
--format zpk` computes them through LAPACKE): the poles those of A, the
zeros those of A - B C / D, the gain D. The sections pair roots by the
rule of tools/host/pfh_lti.c, so that Python and the CLI give the same
cascade: each conjugate pair in one section, and the real roots nearest
z = 1 with the farthest, so that no section holds two poles within 1e-7
of z = 1 that a rounded coefficient would scatter. (scipy's zpk2sos puts
the two poles nearest the unit circle together: these are the ones that
must stay apart.)
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np


class StateSpace(NamedTuple):
    """x[k+1] = A x[k] + B e[k], p_c[k] = C x[k] + D e[k]; sample time dt.
    ``control.ss(*ss)`` takes it as it is."""
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    dt: float


class ZerosPolesGain(NamedTuple):
    """H(z) = k prod(z - z_i) / prod(z - p_i): roots, not corner
    frequencies. ``scipy.signal.freqz_zpk(z, p, k, worN=omega * dt)``."""
    z: np.ndarray
    p: np.ndarray
    k: float
    dt: float


def zpk(ss: StateSpace) -> ZerosPolesGain:
    """Zeros, poles and gain of a state space with D != 0."""
    d = float(ss.D[0, 0])
    if d == 0.0 or not np.isfinite(d):
        raise ValueError("D = 0: the zeros are not the eigenvalues of A - B C / D")
    poles = np.linalg.eigvals(ss.A)
    zeros = np.linalg.eigvals(ss.A - ss.B @ ss.C / d)
    return ZerosPolesGain(zeros.astype(complex), poles.astype(complex), d, ss.dt)


def _quadratics(roots: np.ndarray) -> list[tuple[float, float, float]]:
    """(c1, c2, key): factors 1 + c1 w + c2 w^2 (w = z^-1) of the roots,
    sorted by key, the distance of their nearest root to z = 1."""
    out = []
    for r in roots[roots.imag > 0]:
        out.append((-2.0 * r.real, r.real * r.real + r.imag * r.imag, abs(1.0 - r)))
    real = sorted(roots[roots.imag == 0].real, key=lambda x: abs(1.0 - x))
    n = len(real)
    for i in range((n + 1) // 2):
        r1 = real[i]
        r2 = real[n - 1 - i] if n - 1 - i != i else 0.0
        out.append((-(r1 + r2), r1 * r2, abs(1.0 - r1)))
    return sorted(out, key=lambda q: q[2])


def sos(zpk_: ZerosPolesGain) -> np.ndarray:
    """Second-order sections, rows [b0, b1, b2, 1, a1, a2] (scipy's
    layout, a0 = 1); the gain in the first section."""
    if zpk_.z.size != zpk_.p.size:
        raise ValueError("as many zeros as poles are needed")
    qz, qp = _quadratics(zpk_.z), _quadratics(zpk_.p)
    n = max(len(qz), len(qp), 1)
    out = np.zeros((n, 6))
    out[:, 0] = out[:, 3] = 1.0
    for k, (c1, c2, _) in enumerate(qz):
        out[k, 1:3] = c1, c2
    for k, (c1, c2, _) in enumerate(qp):
        out[k, 4:6] = c1, c2
    out[0, :3] *= zpk_.k
    return out
