# SPDX-License-Identifier: MIT
"""Output-error fitting: the residual is measured minus *simulated* output
(the library run from rest over the whole fit segment), never a one-step
prediction. scipy.optimize.least_squares (trust-region reflective, bounds)
on transformed parameters: logarithms for positive groups, plain values for
orders and limits.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from . import lib, model

SPLIT = 0.7  # fit on the first 70 %, validate on the rest


class _Budget(Exception):
    pass


@dataclass
class Problem:
    """One record, one configuration: data, split and what is held fixed."""
    e: np.ndarray
    y: np.ndarray
    setup: model.Setup
    fixed: dict = field(default_factory=dict)      # group -> value (user or pruned)
    free: list = field(default_factory=list)
    span_e: float = 1.0
    amp_e: float = 1.0
    y_lo: float = 0.0
    y_hi: float = 1.0
    progress: object = None
    entangled: list = field(default_factory=list)
    user_fixed: dict = field(default_factory=dict)

    @property
    def nfit(self) -> int:
        return int(SPLIT * self.e.size)

    @classmethod
    def from_record(cls, rec, config, fixed=None, order=8, oversample=1, progress=None):
        e = rec.e - rec.e0
        y = rec.pc - rec.pc0
        setup = model.Setup(config, rec.fs, rec.n / rec.fs, order, oversample)
        fixed = dict(fixed or {})
        free = [g for g in model.CONFIG_GROUPS[config] if g not in fixed]
        return cls(e, y, setup, fixed, free, float(np.ptp(e)),
                   float(np.max(np.abs(e))), float(np.min(y)), float(np.max(y)),
                   progress=progress)


@dataclass
class FitResult:
    effect: str
    groups: dict                 # all groups (free and fixed)
    effect_params: dict          # report units
    free: list                   # names of fitted parameters (groups + effect)
    theta: np.ndarray
    cost: float                  # RSS on the fit segment
    se: dict = field(default_factory=dict)   # standard error in transformed coords
    ci: dict = field(default_factory=dict)   # name -> (lo, hi), 95 %
    sim: np.ndarray | None = None            # whole-record simulation
    nfit: int = 0
    nrmse_fit: float = math.nan
    nrmse_val: float = math.nan
    bic: float = math.nan
    k: int = 0
    start: str = ""
    values: dict = field(default_factory=dict)   # fitted parameters as fitted
    dead: int = 0
    variant: str = "A"


# -------------------------------------------------------------- parameters
def _effect_specs(effect: str, pb: Problem):
    """(name, transform, lo, hi) of an effect's fitted parameters."""
    fs = pb.setup.fs
    span_y = pb.y_hi - pb.y_lo
    if effect == "lag":
        return [("lag", "log", 0.05 / fs, 0.25 * pb.setup.duration)]
    if effect == "saturation":
        return [("sat_lo", "lin", pb.y_lo - span_y, pb.y_lo + 0.5 * span_y),
                ("sat_hi", "lin", pb.y_hi - 0.5 * span_y, pb.y_hi + span_y)]
    if effect == "backlash":
        return [("deadband", "lin", 0.0, pb.span_e)]
    if effect == "nozzle":   # curvature 1/x_1/2 in 1/input units; 0 = linear nozzle
        return [("nozzle_k", "lin", 0.0, 20.0 / max(pb.amp_e, 1e-300))]
    return []


def specs(pb: Problem, effect: str):
    """(name, transform, lo, hi) of every fitted parameter. The library needs
    nu <= w in the pid configuration: there w is fitted as s in [0, 1] with
    w = nu + (1 - nu) s (transform "wnu"), so that every value tried, and
    every value reported, is one the library simulates as it stands; with
    w held and nu free, nu is bounded by w instead."""
    out = []
    pid = pb.setup.config == "pid"
    for g in pb.free:
        tr, _, _, _ = model.GROUPS[g]
        lo, hi = pb.setup.bounds(g)
        if pid and g == "w":
            tr, lo, hi = "wnu", 0.0, 1.0
        elif pid and g == "nu" and "w" in pb.fixed:
            hi = min(hi, pb.fixed["w"])
        out.append((g, tr, lo, hi))
    return out + _effect_specs(effect, pb)


def _nu(pb: Problem | None, values: dict) -> float:
    nu = values.get("nu")
    if nu is None and pb is not None:
        nu = pb.fixed.get("nu")
    return float(nu)


def w_from_s(nu: float, s: float) -> float:
    return nu + (1.0 - nu) * s


def s_from_w(nu: float, w: float) -> float:
    return min(max((w - nu) / (1.0 - nu), 0.0), 1.0) if nu < 1.0 else 0.0


def _to_theta(sp, values: dict, pb: Problem | None = None) -> np.ndarray:
    th = []
    for name, tr, lo, hi in sp:
        if tr == "wnu":
            th.append(s_from_w(_nu(pb, values), values[name]))
            continue
        v = min(max(values[name], lo), hi)
        th.append(math.log(v) if tr == "log" else v)
    return np.array(th)


def _bounds(sp):
    lo = [math.log(l) if tr == "log" else l for _, tr, l, _ in sp]
    hi = [math.log(h) if tr == "log" else h for _, tr, _, h in sp]
    return np.array(lo), np.array(hi)


def _from_theta(sp, th, pb: Problem | None = None) -> dict:
    out = {name: (math.exp(v) if tr == "log" else float(v))
           for (name, tr, _, _), v in zip(sp, th)}
    for name, tr, _, _ in sp:
        if tr == "wnu":          # s -> w, once nu (free or held) is known
            out[name] = w_from_s(_nu(pb, out), out[name])
    return out


def effect_report(effect: str, vals: dict, fs: float, dead: int = 0) -> dict:
    if effect == "dead_time":
        return {"dead_time": dead / fs, "dead_time_samples": dead}
    if effect == "lag":
        return {"lag": vals["lag"]}
    if effect == "saturation":
        return {"sat_lo": vals["sat_lo"], "sat_hi": vals["sat_hi"]}
    if effect == "backlash":
        return {"deadband": vals["deadband"]}
    if effect == "nozzle":
        k = vals["nozzle_k"]
        return {"nozzle_xh": 1.0 / k if k > 0 else math.inf}
    return {}


def _sim_parts(pb: Problem, effect: str, vals: dict, dead: int):
    g = dict(pb.fixed)
    g.update({k: v for k, v in vals.items() if k in model.GROUPS})
    ev = effect_report(effect, vals, pb.setup.fs, dead)
    if effect == "nozzle" and not math.isfinite(ev["nozzle_xh"]):
        return g, ev, "none"
    if effect == "backlash" and ev["deadband"] <= 0:
        return g, ev, "none"
    return g, ev, effect


def simulate(pb: Problem, effect: str, vals: dict, dead: int = 0, n: int | None = None):
    g, ev, eff = _sim_parts(pb, effect, vals, dead)
    e = pb.e if n is None else pb.e[:n]
    return pb.setup.simulate(g, e, eff, ev)


# ------------------------------------------------------------------ fitting
def _residual_fn(pb, sp, effect, dead, scale, state):
    n = pb.nfit
    y = pb.y[:n]

    def fun(th):
        state["calls"] += 1
        if state["calls"] > state["budget"]:
            raise _Budget()
        vals = _from_theta(sp, th, pb)
        try:
            r = (simulate(pb, effect, vals, dead, n) - y) / scale
        except lib.ModelError:
            r = np.full(n, 1e3)
        c = float(r @ r)
        if not math.isfinite(c):
            r = np.full(n, 1e3)
            c = float(r @ r)
        if c < state["best"][0]:
            state["best"] = (c, np.array(th, copy=True))
        return r
    return fun


def lm_fit(pb: Problem, effect: str, start: dict, dead: int = 0,
           budget: int = 400, label: str = "") -> FitResult:
    """Least squares from one start; returns the best point visited."""
    sp = specs(pb, effect)
    th0 = _to_theta(sp, start, pb)
    lo, hi = _bounds(sp)
    th0 = np.clip(th0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
    scale = max(float(np.std(pb.y[:pb.nfit])), 1e-300)
    state = {"calls": 0, "budget": budget, "best": (math.inf, th0)}
    fun = _residual_fn(pb, sp, effect, dead, scale, state)
    res = None
    try:
        res = least_squares(fun, th0, bounds=(lo, hi), method="trf",
                            x_scale="jac", diff_step=1e-4, xtol=1e-6, ftol=1e-6,
                            gtol=1e-8, max_nfev=budget)
    except _Budget:
        pass
    c, th = state["best"]
    vals = _from_theta(sp, th, pb)
    fr = FitResult(effect, {}, {}, [s[0] for s in sp], th, c * scale * scale,
                   start=label)
    g, ev, _ = _sim_parts(pb, effect, vals, dead)
    fr.groups = g
    fr.effect_params = ev
    fr.values = vals
    fr.dead = dead
    fr.k = len(sp) + (1 if effect == "dead_time" else 0)
    if res is not None and np.allclose(res.x, th):
        fr._jac = res.jac  # type: ignore[attr-defined]
    return fr


def jacobian(pb: Problem, fr: FitResult) -> np.ndarray:
    """d residual / d theta on the fit segment (residual scaled by std(y))."""
    j = getattr(fr, "_jac", None)
    if j is not None:
        return np.asarray(j)
    sp = specs(pb, fr.effect)
    dead = fr.effect_params.get("dead_time_samples", 0)
    scale = max(float(np.std(pb.y[:pb.nfit])), 1e-300)
    state = {"calls": 0, "budget": 10**9, "best": (math.inf, fr.theta)}
    fun = _residual_fn(pb, sp, fr.effect, dead, scale, state)
    r0 = fun(fr.theta)
    lo, hi = _bounds(sp)
    J = np.empty((r0.size, fr.theta.size))
    for i in range(fr.theta.size):
        h = 1e-4 * max(1.0, abs(fr.theta[i]))
        th = fr.theta.copy()
        if th[i] + h > hi[i]:
            h = -h
        th[i] += h
        J[:, i] = (fun(th) - r0) / h
    return J


def uncertainty(pb: Problem, fr: FitResult) -> None:
    """Standard errors and 95 % intervals from s^2 (J^T J)^-1 (pseudo-inverse;
    a direction the data do not determine gets an infinite error)."""
    sp = specs(pb, fr.effect)
    J = jacobian(pb, fr)
    n, p = J.shape
    scale = max(float(np.std(pb.y[:pb.nfit])), 1e-300)
    s2 = fr.cost / (scale * scale) / max(n - p, 1)
    U, S, Vt = np.linalg.svd(J, full_matrices=False)
    tol = S.max() * 1e-7 if S.size and S.max() > 0 else 1.0
    var = np.zeros(p)
    for k in range(S.size):
        if S[k] > tol:
            var += (Vt[k] / S[k]) ** 2
        else:
            var += np.where(np.abs(Vt[k]) > 1e-3, np.inf, 0.0)
    se = np.sqrt(var * s2)
    for (name, tr, lo, hi), th, s in zip(sp, fr.theta, se):
        if tr == "wnu":
            # Reported in w itself (nu taken at its fitted value): the
            # interval is that of w = nu + (1 - nu) s, within [nu, 1].
            nu = _nu(pb, fr.values or fr.groups)
            s = (1.0 - nu) * s
            fr.se[name] = float(s)
            w = w_from_s(nu, th)
            fr.ci[name] = ((None, None) if not math.isfinite(s) else
                           (float(max(nu, w - 1.96 * s)), float(min(1.0, w + 1.96 * s))))
            continue
        fr.se[name] = float(s)
        if not math.isfinite(s) or (tr == "log" and 1.96 * s > 600):
            fr.ci[name] = (None, None)
        elif tr == "log":
            fr.ci[name] = (math.exp(th - 1.96 * s), math.exp(th + 1.96 * s))
        else:
            fr.ci[name] = (th - 1.96 * s, th + 1.96 * s)


def evaluate(pb: Problem, fr: FitResult) -> None:
    """Whole-record simulation, NRMSE on fit and validation parts, BIC."""
    vals = _from_theta(specs(pb, fr.effect), fr.theta, pb)
    dead = fr.effect_params.get("dead_time_samples", 0)
    fr.sim = simulate(pb, fr.effect, vals, dead)
    n = pb.nfit
    r = pb.y - fr.sim
    fr.nfit = n
    fr.nrmse_fit = nrmse(r[:n], pb.y[:n])
    fr.nrmse_val = nrmse(r[n:], pb.y[n:])
    rss = float(r[:n] @ r[:n])
    fr.bic = n * math.log(max(rss, 1e-300) / n) + fr.k * math.log(n)


def nrmse(r, y) -> float:
    d = float(np.sqrt(np.mean((y - np.mean(y)) ** 2)))
    return float(np.sqrt(np.mean(r * r))) / d if d > 0 else math.inf


# ------------------------------------------------------------ start points
def random_starts(pb: Problem, rng: np.random.Generator, m: int) -> list[dict]:
    """Fresh starts spread over the plausible ranges (log-uniform for time
    constants and gains); K is solved linearly afterwards."""
    fs, T = pb.setup.fs, pb.setup.duration
    nom = model.nominal_groups(pb.setup.config)
    out = []
    for _ in range(m):
        g = {}
        for name in pb.free:
            if name == "K":
                g[name] = 1.0
            elif name == "L":
                g[name] = nom["L"] * 10 ** rng.uniform(-1.5, 1.5)
            elif name in ("tau", "RC", "RCd"):
                g[name] = 10 ** rng.uniform(math.log10(1.0 / fs), math.log10(T / 5))
            elif name == "rho":
                g[name] = 10 ** rng.uniform(0.2, 2.0)
            elif name == "RCi_ratio":
                g[name] = 10 ** rng.uniform(0.3, 2.0)
            elif name == "q":
                g[name] = rng.uniform(0.0, 1.0) if nom["q"] > 0 else 0.0
            else:  # orders
                g[name] = rng.uniform(0.4, 1.0)
        if pb.setup.config == "pid":   # the library needs nu <= w
            if "w" in g:
                g["w"] = w_from_s(_nu(pb, g), rng.uniform(0.0, 1.0))
            elif "nu" in g:
                g["nu"] = min(g["nu"], pb.fixed["w"])
        out.append(g)
    return out


def gain_solve(pb: Problem, effect: str, vals: dict, dead: int = 0) -> tuple[dict, float]:
    """Scale K to the least-squares optimum (the output is linear in K for
    every effect except saturation, whose limits are absolute)."""
    v = dict(vals)
    v["K"] = 1.0
    n = pb.nfit
    try:
        s = simulate(pb, effect, v, dead, n)
    except lib.ModelError:
        return v, math.inf
    ss = float(s @ s)
    if not ss > 0 or not math.isfinite(ss):
        return v, math.inf
    k = float(s @ pb.y[:n]) / ss
    if k <= 0:
        return v, math.inf
    if effect == "saturation":
        v["K"] = k
        try:
            r = simulate(pb, effect, v, dead, n) - pb.y[:n]
        except lib.ModelError:
            return v, math.inf
        return v, float(r @ r)
    v["K"] = k
    r = k * s - pb.y[:n]
    return v, float(r @ r)
