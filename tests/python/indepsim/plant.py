# SPDX-License-Identifier: MIT
"""Linear parameter sets: the paper's examples and seeded draws around
them. A draw picks the output-determining groups (docs/analysis.md: K, L,
rho, tau, beta, q, restrictors) and a lever ratio, then maps them back to
physical parameters (a = 1, pmin = 1, ks = 20, k1 = k2), so the truth file
can give both."""
from __future__ import annotations

import math

import numpy as np

from . import controller

PAPER = {
    "p": {"a": 1.0, "b": 9.0, "k1": 0.1, "k2": 0.1, "A": 2.0, "ks": 20.0, "tau": 1e-3,
          "pmin": 1.0, "pmax": 10.0, "beta": 0.8, "q": 0.9},           # Example 4
}
PAPER["dd"] = dict(PAPER["p"], nu=0.94, RC=0.1)                        # Example 6
PAPER["id"] = dict(PAPER["p"], k1=2.0, k2=5.0, q=0.0, w=0.94, RC=0.1)   # Example 7
# pid: Example 7's values, nu = w = 0.94, RCd = 0.01 s, RCi = 0.1 s (docs/pid.md)
PAPER["pid"] = {k: v for k, v in PAPER["id"].items() if k != "RC"}
PAPER["pid"].update(nu=0.94, RCd=0.01, RCi=0.1)

# Spreads: "near" stays close to the paper's example (time constants within
# x/÷1.4, gains x/÷1.25, orders +-0.05, loop gain as in the paper); "wide"
# goes beyond it (loop gains that the record can see, orders 0.6-1).
SPREADS = ("near", "wide")


def _logu(rng, centre: float, lo_dec: float, hi_dec: float) -> float:
    return float(centre * 10.0 ** rng.uniform(lo_dec, hi_dec))


def _groups(config: str, spread: str, rng: np.random.Generator) -> dict:
    p0 = PAPER[config]
    g0 = controller.groups(config, p0)
    near = spread == "near"
    w14, w125 = math.log10(1.4), math.log10(1.25)
    g = {"K": _logu(rng, g0["K"], -w125, w125) if near else _logu(rng, g0["K"], -0.5, 0.5),
         "tau": _logu(rng, g0["tau"], -w14, w14) if near else _logu(rng, g0["tau"], -0.5, 0.5),
         "rho": _logu(rng, g0["rho"], -w125, w125) if near else _logu(rng, 1.0, 0.5, 1.5),
         "beta": float(np.clip(g0["beta"] + rng.uniform(-0.05, 0.05), 0.05, 1.0)) if near
         else float(rng.uniform(0.6, 1.0))}
    if config in ("p", "dd"):
        g["L"] = _logu(rng, g0["L"], -w125, w125) if near else _logu(rng, 1e-4, 0.0, 3.3)
        g["q"] = float(np.clip(g0["q"] + rng.uniform(-0.05, 0.05), 0.0, 1.0)) if near \
            else float(rng.uniform(0.8, 1.0))
    else:
        g["L"] = _logu(rng, g0["L"], -w125, w125) if near else _logu(rng, g0["L"], -0.5, 0.5)
        g["q"] = 0.0 if near or rng.uniform() < 0.5 else float(rng.uniform(0.0, 0.3))
    if config == "dd":
        g["RC"] = _logu(rng, 0.1, -w14, w14) if near else _logu(rng, 0.1, -0.7, 0.5)
        g["nu"] = float(np.clip(0.94 + rng.uniform(-0.05, 0.05), 0.05, 1.0)) if near \
            else float(rng.uniform(0.75, 1.0))
    if config == "id":
        g["RC"] = _logu(rng, 0.1, -w14, w14) if near else _logu(rng, 0.1, -0.5, 0.7)
        g["w"] = float(np.clip(0.94 + rng.uniform(-0.05, 0.05), 0.05, 1.0)) if near \
            else float(rng.uniform(0.75, 1.0))
    if config == "pid":
        if near:
            g["nu"] = float(np.clip(0.94 + rng.uniform(-0.05, 0.05), 0.05, 1.0))
            g["w"] = float(np.clip(0.94 + rng.uniform(-0.05, 0.05), g["nu"], 1.0))
            g["RCd"] = _logu(rng, 0.01, -w14, w14)
            g["RCi"] = _logu(rng, 0.1, -w14, w14)
        else:
            g["nu"] = float(rng.uniform(0.75, 1.0))
            g["w"] = float(rng.uniform(g["nu"], 1.0))
            g["RCd"] = _logu(rng, 0.01, -0.3, 0.5)
            g["RCi"] = g["RCd"] * 10.0 ** float(rng.uniform(0.7, 1.3))
    return g


def physical(config: str, g: dict, b_over_a: float) -> dict:
    """Physical parameters with these groups: a = 1, pmin = 1, ks = 20,
    k1 = k2 = sqrt(K/ce), A from L."""
    a, b = 1.0, b_over_a
    ce, cy = b / (a + b), a / (a + b)
    k = math.sqrt(g["K"] / ce)
    p = {"a": a, "b": b, "k1": k, "k2": k, "ks": 20.0, "pmin": 1.0, "pmax": g["rho"],
         "tau": g["tau"], "beta": g["beta"], "q": g["q"]}
    p["A"] = p["ks"] * g["L"] / (cy * k * k)
    for name in ("RC", "nu", "w", "RCd", "RCi"):
        if name in g:
            p[name] = g[name]
    return p


def draw(config: str, spread: str, rng: np.random.Generator) -> dict:
    """A stable parameter set (checked on the closed loop's poles)."""
    if spread not in SPREADS:
        raise ValueError(f"unknown spread {spread}")
    for _ in range(50):
        g = _groups(config, spread, rng)
        b_over_a = 9.0 if spread == "near" else float(rng.uniform(4.0, 19.0))
        p = physical(config, g, b_over_a)
        ss = controller.build(config, p, (1e-3, 1e5))
        if controller.stable(ss):
            return p
    raise RuntimeError("no stable parameter set drawn")
