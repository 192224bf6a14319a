# SPDX-License-Identifier: MIT
"""The ideal (irrational) controller: the paper's transfer functions at
complex s, for the Bode comparison with the realised one.

P_c/E = g R / (1 + c R B M), with g = b k1 k2/(a+b), c = a k1 k2/(a+b),
the relay R = (1 + (tau s)^beta)/(pmin + pmax (tau s)^beta) (eqs. 11-14),
the bellows B = (A/ks) s^-q (eq. 16) and the restrictor term M: 1 (p,
eq. 17), 1/(RC s^nu + 1) (dd, eq. 18), RC s^w/(RC s^w + 1) (id, eq. 20),
(RCi s^w - RCd s^nu)/((RCd s^nu + 1)(RCi s^w + 1)) (pid, docs/pid.md).
Powers take the principal branch. The output line of the lag and dead-time
effects is e^(-s T)/(1 + s lag).

This is the closed form that tools/host/pfh_ref.c evaluates for `pneufrac
bode`; the C host library is not part of an installed prefix, so the
Python API evaluates it with numpy, and tests/python/test_api_design.py
holds the two to the same numbers.
"""
from __future__ import annotations

import numpy as np


def _ppow(s: np.ndarray, e: float) -> np.ndarray:
    """Principal s^e; exponents 0 and 1 exact (q = 0 is a linear spring)."""
    if e == 0.0:
        return np.ones_like(s)
    if e == 1.0:
        return s
    return np.exp(e * np.log(s))


def controller(config: str, p: dict, s) -> np.ndarray:
    """P_c/E of configuration @config with paper parameters @p at @s."""
    s = np.asarray(s, dtype=complex)
    g = p["b"] * p["k1"] * p["k2"] / (p["a"] + p["b"])
    c = p["a"] * p["k1"] * p["k2"] / (p["a"] + p["b"])
    u = _ppow(p["tau"] * s, p["beta"])
    relay = (1.0 + u) / (p["pmin"] + p["pmax"] * u)
    bellows = (p["A"] / p["ks"]) / _ppow(s, p["q"])
    # Common denominators, so that no digits cancel where |RC s^x| is small.
    if config == "dd":
        m = 1.0 / (p["RC"] * _ppow(s, p["nu"]) + 1.0)
    elif config == "id":
        xi = p["RC"] * _ppow(s, p["w"])
        m = xi / (xi + 1.0)
    elif config == "pid":
        xd = p["RCd"] * _ppow(s, p["nu"])
        xi = p["RCi"] * _ppow(s, p["w"])
        m = (xi - xd) / ((xd + 1.0) * (xi + 1.0))
    elif config == "p":
        m = 1.0
    else:
        raise ValueError(f"unknown configuration '{config}'")
    return g * relay / (1.0 + c * relay * bellows * m)


def line(dead_time: float, lag: float, s) -> np.ndarray:
    """The output line of the linear effects, e^(-s dead_time)/(1 + s lag)."""
    s = np.asarray(s, dtype=complex)
    out = np.ones_like(s)
    if lag > 0.0:
        out = out / (1.0 + lag * s)
    if dead_time > 0.0:
        out = out * np.exp(-dead_time * s)
    return out
