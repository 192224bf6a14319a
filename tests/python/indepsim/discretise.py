# SPDX-License-Identifier: MIT
"""Exact discretisation of a continuous state space for inputs that are
linear between samples (first-order hold, FOH), by one matrix exponential
of the augmented system (Franklin, Powell & Workman, "Digital Control of
Dynamic Systems", 3rd ed., sec. 6.3.2).

    x[n+1] = Phi x[n] + G0 u[n] + G1 u[n+1],   y[n] = C x[n] + D u[n]

Unlike the library's Tustin discretisation of each operator, the whole
closed loop is integrated exactly between internal samples; the only
assumption is on the inputs' shape between them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from .netlist import StateSpace


@dataclass
class Discrete:
    Phi: np.ndarray
    G0: np.ndarray
    G1: np.ndarray
    C: np.ndarray
    D: np.ndarray
    h: float


def foh(ss: StateSpace, h: float) -> Discrete:
    n, m = ss.B.shape
    big = np.zeros((n + 2 * m, n + 2 * m))
    big[:n, :n] = ss.A * h
    big[:n, n:n + m] = ss.B * h
    big[n:n + m, n + m:] = np.eye(m)      # u' = (u[n+1] - u[n]) / h
    E = expm(big)
    Phi, Ga, Gb = E[:n, :n], E[:n, n:n + m], E[:n, n + m:]
    return Discrete(Phi, Ga - Gb, Gb, ss.C.copy(), ss.D.copy(), h)
