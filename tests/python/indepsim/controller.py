# SPDX-License-Identifier: MIT
"""The paper's controllers as block diagrams (Figs. 3, 5, 7; pid as in
docs/pid.md), in physical parameters named as in the paper.

    x    = b/(a+b) e - a/(a+b) y              flapper lever, eq. 15
    xf   = nozzle(play(x))                    flapper gap (effects; else x)
    p_b  = k1 xf                              nozzle, eq. 9
    z    = (p_b + I(p_b - pmin z)) / pmax,  I = (tau s)^-beta
           i.e. Z/P_b = (1+(tau s)^beta)/(pmin+pmax (tau s)^beta), eqs. 11-12
    p_c  = k2 z                               eq. 13, then clipped (effect)
    r    = (1/RC) s^-nu (p_c - r)             restrictor 1/(RC s^nu + 1)
    m    = p_c | r_v | p_c - r_w | r_v - r_w  p, dd, id, pid
    y    = (A/ks) s^-q m                      bellows, eq. 16
    line = p_c through an optional first-order lag (output line)
"""
from __future__ import annotations

import math

import numpy as np

from .diffusive import Modes, frac_integrator
from .netlist import Net, StateSpace

CONFIGS = ("p", "dd", "id", "pid")
PAPER_NAMES = ("a", "b", "k1", "k2", "A", "ks", "tau", "pmin", "pmax", "beta", "q",
               "nu", "w", "RC", "RCd", "RCi")


def used(config: str) -> tuple[str, ...]:
    """Parameter names a configuration uses."""
    base = ("a", "b", "k1", "k2", "A", "ks", "tau", "pmin", "pmax", "beta", "q")
    extra = {"p": (), "dd": ("nu", "RC"), "id": ("w", "RC"), "pid": ("nu", "w", "RCd", "RCi")}
    return base + extra[config]


def groups(config: str, p: dict) -> dict:
    """The output-determining groups as docs/analysis.md defines them."""
    ce, cy = p["b"] / (p["a"] + p["b"]), p["a"] / (p["a"] + p["b"])
    g = {"K": ce * p["k1"] * p["k2"] / p["pmin"],
         "L": cy * p["k1"] * p["k2"] * (p["A"] / p["ks"]) / p["pmin"],
         "rho": p["pmax"] / p["pmin"], "tau": p["tau"], "beta": p["beta"], "q": p["q"]}
    if config in ("dd", "id"):
        g["RC"] = p["RC"]
    if config in ("dd", "pid"):
        g["nu"] = p["nu"]
    if config in ("id", "pid"):
        g["w"] = p["w"]
    if config == "pid":
        g["RCd"], g["RCi"] = p["RCd"], p["RCi"]
    return g


def lever(p: dict) -> tuple[float, float]:
    """ce = b/(a+b) (x per unit e) and cy = a/(a+b)."""
    return p["b"] / (p["a"] + p["b"]), p["a"] / (p["a"] + p["b"])


def _restrictor(net: Net, name: str, inp: str, order: float, rc: float,
                band: tuple[float, float]) -> None:
    net.junction(name + "_in", {inp: 1.0, name: -1.0})
    net.block(name, name + "_in", frac_integrator(order, *band), 1.0 / rc)


def build(config: str, p: dict, band: tuple[float, float], lag: float = 0.0,
          open_x: bool = False, open_pc: bool = False, wind: bool = False) -> StateSpace:
    """Closed-loop state space. Inputs: e, then xf if open_x, then pcs if
    open_pc (the outputs of the in-loop effects, fed back by the caller).
    Outputs: x (flapper displacement), pc (relay output before any clip),
    line (output line, after the lag). wind (with open_pc): the relay's
    integral sees the stopped z = pcs/k2 instead of its own z (the stop
    acts on the stroke the diaphragm drives, the diaphragm stays loaded
    by the whole p_b), so it winds on while the output is held."""
    if config not in CONFIGS:
        raise ValueError(f"unknown configuration {config}")
    ce, cy = lever(p)
    inputs = ["e"] + (["xf"] if open_x else []) + (["pcs"] if open_pc else [])
    net = Net(inputs)
    net.junction("x", {"e": ce, "y": -cy})
    if not open_x:
        net.junction("xf", {"x": 1.0})
    net.junction("pb", {"xf": p["k1"]})
    if wind and open_pc:
        net.junction("relay_in", {"pb": 1.0, "pcs": -p["pmin"] / p["k2"]})
    else:
        net.junction("relay_in", {"pb": 1.0, "z": -p["pmin"]})
    net.block("relay_i", "relay_in", frac_integrator(p["beta"], *band), p["tau"] ** -p["beta"])
    net.junction("z", {"pb": 1.0 / p["pmax"], "relay_i": 1.0 / p["pmax"]})
    net.junction("pc", {"z": p["k2"]})
    if not open_pc:
        net.junction("pcs", {"pc": 1.0})
    if config == "p":
        net.junction("m", {"pcs": 1.0})
    elif config == "dd":
        _restrictor(net, "rv", "pcs", p["nu"], p["RC"], band)
        net.junction("m", {"rv": 1.0})
    elif config == "id":
        _restrictor(net, "rw", "pcs", p["w"], p["RC"], band)
        net.junction("m", {"pcs": 1.0, "rw": -1.0})
    else:
        _restrictor(net, "rv", "pcs", p["nu"], p["RCd"], band)
        _restrictor(net, "rw", "pcs", p["w"], p["RCi"], band)
        net.junction("m", {"rv": 1.0, "rw": -1.0})
    net.block("y", "m", frac_integrator(p["q"], *band), p["A"] / p["ks"])
    if lag > 0.0:
        net.block("line", "pcs", Modes(np.array([1.0 / lag]), np.array([1.0 / lag]), 0.0))
    else:
        net.junction("line", {"pcs": 1.0})
    return net.close(["x", "pc", "line"])


def exact_tf(config: str, p: dict, s: np.ndarray) -> np.ndarray:
    """P_c/E of the irrational model at complex s (principal powers): the
    paper's eqs. 17, 18, 20 and docs/pid.md in their unreduced loop form."""
    s = np.asarray(s, dtype=complex)
    ce, cy = lever(p)
    ts = (p["tau"] * s) ** p["beta"]
    G = p["k1"] * p["k2"] * (1.0 + ts) / (p["pmin"] + p["pmax"] * ts)
    rv = (lambda rc: 1.0 / (rc * s ** p["nu"] + 1.0))
    rw = (lambda rc: 1.0 / (rc * s ** p["w"] + 1.0))
    M = {"p": lambda: 1.0, "dd": lambda: rv(p["RC"]), "id": lambda: 1.0 - rw(p["RC"]),
         "pid": lambda: rv(p["RCd"]) - rw(p["RCi"])}[config]()
    return ce * G / (1.0 + cy * G * (p["A"] / p["ks"]) * s ** (-p["q"]) * M)


def stable(ss: StateSpace, tol: float = 1e-9) -> bool:
    """No closed-loop pole in the right half plane (integrators allowed)."""
    ev = np.linalg.eigvals(ss.A)
    scale = max(1.0, float(np.max(np.abs(ev)))) if ev.size else 1.0
    return bool(np.all(ev.real <= tol * scale))


def band_for(fs_internal: float, duration: float) -> tuple[float, float]:
    """Quadrature band: 1e-3 of the record's lowest frequency up to ten times
    the internal Nyquist frequency (faster modes are settled within one
    internal step; the tail pole covers the rest)."""
    return (1e-3 * 2.0 * math.pi / max(duration, 1e-3), 10.0 * math.pi * fs_internal)
