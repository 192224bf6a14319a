# SPDX-License-Identifier: MIT
"""Output-error fitting: the residual is measured minus *simulated* output
(the library run from rest over the whole fit segment), never a one-step
prediction. scipy.optimize.least_squares (trust-region reflective, bounds)
on transformed parameters: logarithms for positive groups, plain values for
orders and limits.

The output is linear in the forward gain K (for every effect but
saturation, whose limits are absolute) and in the output offset pc0, so
both are solved by linear least squares inside every evaluation (variable
projection): the search never wanders along them.

With a noise model (Problem.nm, an AR model A(q) of the residual, noise.py)
the criterion is prewhitened: the residual, and the regressors of K and
pc0, are filtered by A(q) before the sum of squares. That is the likelihood
of the output under that noise: under strongly coloured noise an unweighted
output error chases the noise's slow wander and weighs it like evidence. The finite-difference
Jacobian runs its columns on parallel threads (the library call releases
the interpreter lock).
"""
from __future__ import annotations

import copy
import functools
import math
import os
import threading
from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from . import digest, holdout, lib, model, noise

NOZZLE_BIAS = (-0.5, 3.0)   # the fitted range of the nozzle's bias point
BURN = 0.02          # without an opening rest (of at least this much): 2 % of the fit part's samples, at the start, not counted
DIFF_STEP = 1e-4     # relative finite-difference step (transformed parameters)
# A search's Jacobians after its first are made at half the simulation
# rate while each step still saves more than COARSE_DEVIANCE in deviance,
# then at the full rate to the end (_Objective.jac); 0: always at the full
# rate.
COARSE_DEVIANCE = 10.0

_pool = None
_pool_pid = 0
_threads = 1
_TRACE = bool(os.environ.get("PNEUFRAC_FIT_TRACE"))


def set_threads(n: int) -> None:
    """Threads for the Jacobian's columns (one per core is right). A forked
    worker process inherits the parent's pool but not its threads: it makes
    its own."""
    global _pool, _threads, _pool_pid
    n = max(1, int(n))
    forked = _pool is not None and _pool_pid != os.getpid()
    if forked:
        _pool = None             # the parent's: its threads are not here
    if n != _threads or (_pool is None and n > 1):
        if _pool is not None:
            _pool.shutdown(wait=True)
        _pool = ThreadPoolExecutor(max_workers=n) if n > 1 else None
        _pool_pid = os.getpid()
        _threads = n


class _Budget(Exception):
    pass


@dataclass
class Problem:
    """One record, one configuration: data, split and what is held fixed.
    The split (holdout.Split) says which samples the fit counts (from burn
    on) and which are held out; nothing else does."""
    e_abs: np.ndarray            # measured input
    y: np.ndarray                # measured output
    setup: model.Setup
    fixed: dict = field(default_factory=dict)      # group -> value (user or pruned)
    free: list = field(default_factory=list)       # groups fitted ("e0" included when fitted)
    split: holdout.Split = None  # fit parts and held-out blocks
    burn: int = 0                # first sample counted in the cost (in the first fit part)
    pc0: float | None = None     # output offset given (None: solved)
    span_e: float = 1.0
    amp_e: float = 1.0
    y_lo: float = 0.0            # range of the output deviation
    y_hi: float = 1.0
    entangled: list = field(default_factory=list)
    user_fixed: dict = field(default_factory=dict)
    at_bound: dict = field(default_factory=dict)   # group -> bound it is held at
    nm: object = None            # noise model: the criterion is whitened by it
    held: dict = field(default_factory=dict)      # effect parameters held, not fitted (a profile)
    open_start: bool = False     # the state at the first sample is unknown (no opening rest)

    @classmethod
    def from_record(cls, rec, config, fixed=None, order=8, oversample=1, split=None):
        n = rec.n
        split = split or holdout.layout(n)
        nfit = split.n_fit
        fixed = dict(fixed or {})
        if rec.e0 is not None:
            fixed["e0"] = rec.e0
        free = [g for g in model.CONFIG_GROUPS[config] if g not in fixed]
        if "e0" not in fixed:
            free.append("e0")
        setup = model.Setup(config, rec.fs, n / rec.fs, order, oversample)
        at_rest = rec.e0 is not None and rec.rest >= BURN * nfit
        if rec.e0 is not None and rec.rest and not at_rest:
            # A short stillness of the input does not show that the
            # controller rests: its slow modes move the output less than
            # the noise over a few tens of samples (an own-generator pid
            # record cut from a longer one opened with the input held 54
            # samples; fitted from rest its held-out NRMSE was 0.11, floor
            # 0.014). The rest must last as long as the stretch that is not
            # counted without one.
            rec.notes.append(f"the opening rest ({rec.rest} samples) is shorter than "
                             f"{BURN:.0%} of the fit part: it does not show that the "
                             "controller was at rest, so its state at the start is "
                             "estimated too (a decaying free response)")
        burn = 0 if at_rest else min(max(1, int(BURN * nfit)), split.first_end // 2)
        pc0 = rec.pc0 if getattr(rec, "op_given", False) else None
        e = rec.e - (rec.e0 if rec.e0 is not None else float(np.median(rec.e[:10])))
        # the output's range over the fit parts: no held-out output reaches the fit
        yd = (np.concatenate([rec.pc[s] for s in split.fit_slices()])
              - (rec.pc0 if rec.pc0 is not None else float(np.median(rec.pc[:10]))))
        return cls(np.asarray(rec.e, float), np.asarray(rec.pc, float), setup, fixed, free,
                   split, burn, pc0, float(np.ptp(rec.e)), float(np.max(np.abs(e))),
                   float(np.min(yd)), float(np.max(yd)), open_start=burn > 0)

    def e0_default(self) -> float:
        """Where e0 is held if the record does not determine it: the input's
        opening level."""
        return float(np.median(self.e_abs[:10]))

    def window(self, n: int) -> "Problem":
        """The same problem fitted on its first n samples only."""
        import copy
        w = copy.copy(self)
        w.split = self.split.window(n)
        return w

    @property
    def nsim(self) -> int:
        """Samples the fit simulates (to the end of its last part)."""
        return _split_end(self.split)

    @property
    def fit_parts(self) -> list:
        """The samples the fit counts: slices from burn on."""
        return list(_fit_slices(self.split, self.burn))

    @property
    def held_parts(self) -> list:
        return self.split.held_slices()

    @property
    def n_counted(self) -> int:
        return sum(s.stop - s.start for s in self.fit_parts)

    def fit_of(self, x: np.ndarray) -> np.ndarray:
        """x's samples in the fit parts, concatenated."""
        return noise.whiten_parts(None, x, self.fit_parts)

    def held_of(self, x: np.ndarray) -> np.ndarray:
        """x's samples in the held-out parts, concatenated."""
        return noise.whiten_parts(None, x, self.held_parts)

    def fit_pieces(self, x: np.ndarray, start: int = 0) -> list:
        """x's samples in each fit part from sample start on, one array per
        part (what a noise model of the residual is fitted to: noise.fit
        pairs no samples across a held-out block)."""
        return [x[s] for s in self.split.fit_slices(max(self.burn, start))]

    def fit_white(self, x: np.ndarray, nm=False) -> np.ndarray:
        """x over the fit parts, each whitened on its own by nm (default:
        the problem's noise model; None: not whitened)."""
        return noise.whiten_parts(self.nm if nm is False else nm, x, self.fit_parts)

    def held_white(self, x: np.ndarray, nm) -> np.ndarray:
        return noise.whiten_parts(nm, x, self.held_parts)


# A split's part arithmetic, asked several times for every evaluation of a
# fit (nsim, fit_parts: about 1 % of a diagnosis's Python side), kept per
# split and burn: a Split is frozen (holdout.Split), so the answer for one
# is fixed.
@functools.lru_cache(maxsize=64)
def _fit_slices(split, burn: int) -> tuple:
    return tuple(split.fit_slices(burn))


@functools.lru_cache(maxsize=64)
def _split_end(split) -> int:
    return split.end


@dataclass
class FitResult:
    effects: tuple               # canonical set of effects
    groups: dict                 # all groups (free and fixed), K included
    values: dict                 # fitted parameters as fitted (+ K, pc0)
    names: list                  # LM parameter names, in theta order
    theta: np.ndarray
    cost: float                  # RSS over the counted fit samples
    dead: int = 0                # dead time, samples of the simulation rate
    k: int = 0                   # parameters counted by BIC
    K_solved: bool = True
    pc0_solved: bool = True
    se: dict = field(default_factory=dict)
    ci: dict = field(default_factory=dict)
    sim: np.ndarray | None = None            # whole-record model output (absolute)
    nrmse_fit: float = math.nan
    nrmse_val: float = math.nan
    bic: float = math.nan
    start: str = ""
    free_groups: list = field(default_factory=list)   # groups free in this fit
    jac: np.ndarray | None = None
    noise: object = None     # the noise model of the intervals (uncertainty)
    start_coef: np.ndarray | None = None     # the start's free response (open_start) ...
    start_taus: tuple = ()                   # ... its time constants (samples)
    owed: object = None      # the problem whose intervals are owed (uncertainty_later)

    @property
    def effect(self) -> str:
        """One name for the model: 'none', an effect, or 'a+b'."""
        return "+".join(self.effects) if self.effects else "none"

    @property
    def e0(self) -> float:
        return self.values.get("e0", self.groups.get("e0", 0.0))

    def effect_params(self, fs_int: float, m: int) -> dict:
        """Report units; saturation limits absolute (the model's offset
        pc0 added to the limits on its simulated deviation)."""
        p = effect_report(self.effects, self.values, fs_int, m, self.dead)
        if "sat_lo" in p:
            p["sat_lo"] += self.values.get("pc0", 0.0)
            p["sat_hi"] += self.values.get("pc0", 0.0)
        return p

    def residual(self, pb: Problem) -> np.ndarray:
        return pb.y - self.sim


# -------------------------------------------------------------- parameters
def _effect_specs(effects, pb: Problem):
    """(name, transform, lo, hi) of the effects' fitted parameters."""
    fs = pb.setup.fs
    span_y = pb.y_hi - pb.y_lo
    out = []
    for eff in effects:
        if eff == "lag":
            out.append(("lag", "log", 0.02 / fs, 0.25 * pb.setup.duration))
        elif eff == "saturation":
            out += [("sat_lo", "lin", pb.y_lo - span_y, pb.y_lo + 0.5 * span_y),
                    ("sat_hi", "lin", pb.y_hi - 0.5 * span_y, pb.y_hi + span_y)]
        elif eff == "backlash":
            out.append(("deadband", "lin", 0.0, pb.span_e))
        elif eff == "nozzle":   # curvature 1/x_1/2 in 1/input units; 0 = linear nozzle
            out.append(("nozzle_k", "lin", 0.0, 20.0 / max(pb.amp_e, 1e-300)))
            # the bias point: the equilibrium's gap above the curve's
            # inflection, units of x_1/2 (the library's range, to 3)
            out.append(("nozzle_bias", "lin", NOZZLE_BIAS[0], NOZZLE_BIAS[1]))
    return [s for s in out if s[0] not in pb.held]


def solves_K(pb: Problem, effects) -> bool:
    return "K" not in pb.fixed and "saturation" not in effects


def specs(pb: Problem, effects):
    """(name, transform, lo, hi) of every parameter the search moves. The
    library needs nu <= w in the pid configuration: there w is fitted as s
    in [0, 1] with w = nu + (1 - nu) s (transform "wnu"), so that every value
    tried, and every value reported, is one the library simulates; with w
    held and nu free, nu is bounded by w instead."""
    out = []
    pid = pb.setup.config == "pid"
    skipK = solves_K(pb, effects)
    for g in pb.free:
        if g == "K" and skipK:
            continue
        if g == "e0":
            lo, hi = float(np.min(pb.e_abs)), float(np.max(pb.e_abs))
            pad = max(hi - lo, 1e-12)
            out.append(("e0", "lin", lo - pad, hi + pad))
            continue
        tr, _, _, _ = model.GROUPS[g]
        lo, hi = pb.setup.bounds(g)
        if pid and g == "w":
            tr, lo, hi = "wnu", 0.0, 1.0
        elif pid and g == "nu" and "w" in pb.fixed:
            hi = min(hi, pb.fixed["w"])
        out.append((g, tr, lo, hi))
    return out + _effect_specs(effects, pb)


def _nu(pb: Problem | None, values: dict) -> float:
    nu = values.get("nu")
    if nu is None and pb is not None:
        nu = pb.fixed.get("nu")
    return float(nu)


def w_from_s(nu: float, s: float) -> float:
    return nu + (1.0 - nu) * s


def s_from_w(nu: float, w: float) -> float:
    return min(max((w - nu) / (1.0 - nu), 0.0), 1.0) if nu < 1.0 else 0.0


def to_theta(sp, values: dict, pb: Problem | None = None) -> np.ndarray:
    th = []
    for name, tr, lo, hi in sp:
        if tr == "wnu":
            th.append(s_from_w(_nu(pb, values), values[name]))
            continue
        v = min(max(values[name], lo), hi)
        th.append(math.log(v) if tr == "log" else v)
    return np.array(th, float)


def bounds(sp):
    lo = [math.log(l) if tr == "log" else l for _, tr, l, _ in sp]
    hi = [math.log(h) if tr == "log" else h for _, tr, _, h in sp]
    return np.array(lo, float), np.array(hi, float)


def from_theta(sp, th, pb: Problem | None = None) -> dict:
    out = {name: (math.exp(v) if tr == "log" else float(v))
           for (name, tr, _, _), v in zip(sp, th)}
    for name, tr, _, _ in sp:
        if tr == "wnu":          # s -> w, once nu (free or held) is known
            out[name] = w_from_s(_nu(pb, out), out[name])
    return out


def effect_report(effects, vals: dict, fs_int: float, m: int, dead: int = 0) -> dict:
    """Effect parameters in report units (dead time in s and data samples)."""
    out = {}
    for eff in effects:
        if eff == "dead_time":
            out.update(dead_time=dead / fs_int, dead_time_samples=dead / m)
        elif eff == "lag":
            out["lag"] = vals["lag"]
        elif eff == "saturation":
            out.update(sat_lo=vals["sat_lo"], sat_hi=vals["sat_hi"],
                       sat_kind=model.sat_kind(vals),
                       sat_kind_told=float(vals.get("sat_kind_told", 0.0)))
        elif eff == "backlash":
            out["deadband"] = vals["deadband"]
        elif eff == "nozzle":
            k = vals["nozzle_k"]
            out["nozzle_xh"] = 1.0 / k if k > 0 else math.inf
            out["nozzle_bias"] = vals.get("nozzle_bias", 0.0)
    return out


# -------------------------------------------------------------- simulation
def _groups(pb: Problem, vals: dict) -> dict:
    """Every group (and e0): the held ones from pb, the free ones from vals
    (a start may carry values of held groups: they do not count)."""
    g = {k: v for k, v in pb.fixed.items()}
    g.update({k: v for k, v in vals.items() if k in pb.free or k == "K"})
    g.setdefault("K", 1.0)
    return g


def simulate_raw(pb: Problem, effects, vals: dict, dead: int = 0, n: int | None = None,
                 oversample: int | None = None) -> np.ndarray:
    """The library's output (deviation, at the groups' K) over the first n
    samples, for input e_abs - e0."""
    g = _groups(pb, vals)
    ev = {**pb.held, **vals}
    ev["dead"] = dead
    return pb.setup.simulate(g, _input(pb.e_abs, n, g["e0"]), effects, ev, oversample)


def _input(e_abs: np.ndarray, n: int | None, e0) -> np.ndarray:
    """e_abs[:n] - e0, read only. A Jacobian simulates one record's input at
    the same e0 for every column but e0's, and each subtraction (and the
    hold that model.held_input makes of its result) is a pass over the
    record: the last few are kept (_INPUTS), keyed by the record's array
    (no code writes into a problem's e_abs, as _fixed_regressors assumes of
    its y), n and e0's bits (0.0 and -0.0 are different keys: their
    differences differ in the sign of a zero)."""
    e = e_abs if n is None else e_abs[:n]
    return _INPUTS.get(e_abs, (n, float(e0).hex()), lambda: e - e0)


_INPUTS = model.DerivedArrays(8)   # a few records' inputs at a few e0, each a record long


# ------------------------------------------------------- the unknown start
# A record that does not open at rest opens in the middle of a response:
# the controller's state at its first sample holds the past input, which
# the record does not contain. Simulated from rest, the model meets the
# record with a wrong state, and the difference is the model's free
# response, which dies away with the model's own modes. The slow ones are
# fractional (the reset restrictor, the bellows, the relay diaphragm): a
# spread of time constants up to the record's length, so the difference
# decays over seconds, not samples (a pid record cut from a longer one: 100
# noise sd at the start, 9 at 0.1-0.2 s, 2 at 0.2-0.5 s with the true
# parameters). An output-error fit then bends the dynamics to follow that
# transient. The free response is not known, but it is a smooth decaying
# function of time: a sum of exponentials exp(-t/T) whose time constants
# spread geometrically over the modes' range (a completely monotone decay
# is what such sums approximate). Its coefficients enter linearly, like
# the offset pc0, so they are solved inside every evaluation with K and
# pc0 (the initial conditions of output-error identification as free
# linear parameters). Time constants: from a third of the default burn
# (BURN of the fit part) up to a ninth of the first fit part (START_SPAN), a
# factor START_STEP apart: every term has died away (to e^-9) by the end
# of the first fit part, before the first held-out sample, so none can
# stand in for a trend or a slow noise across the record. With terms up to a third of the fit part, 1/f sensor noise (whose
# slow wander looks like a decay over the fit part) let the slow groups
# move for it: on two own-generator pid records with 1/f noise the held-out
# NRMSE went from 0.044 to 0.17 and from 0.037 to 0.078. A time constant whose exponential has fallen below
# START_GONE by the first counted sample is left out (where a comparison
# discounts more of the start, as with a dead band). The same basis for
# every model of one problem, so every comparison gives both models the
# same freedom.
START_STEP = 3.0
START_SPAN = 9.0
START_GONE = 1e-3
_CONSTANTS: dict = {}     # a problem's whitened constant regressors (see _remember)


def start_taus(pb: Problem) -> tuple:
    """Time constants (samples) of the start's free-response basis; none
    when the record opens at rest (the state is known: rest). Every
    evaluation of the model asks for them twice (model_output, project),
    and the split's part arithmetic costs about a twentieth of a
    simulation's Python side: kept per split, burn and the constants, all
    they depend on (_start_taus)."""
    if not pb.open_start:
        return ()
    return _start_taus(pb.split, pb.burn, BURN, START_STEP, START_SPAN, START_GONE)


@functools.lru_cache(maxsize=64)
def _start_taus(split, burn: int, burn_share: float, step: float, span: float,
                gone: float) -> tuple:
    t, out = max(burn_share * split.n_fit, 1.0) / step, []
    while t <= split.first_end / span:
        if math.exp(-burn / t) >= gone:
            out.append(t)
        t *= step
    return tuple(out)


def start_basis(taus, n: int) -> np.ndarray:
    """The basis of these time constants over samples 0..n-1 (n x m), read
    only. Every evaluation of a problem's model adds it (model_output), and
    its n m exponentials cost about a tenth of the simulation: made once
    for each set of taus, at the longest n asked for, and kept (_BASES);
    a shorter one is its first rows (each row depends on its sample alone,
    so they are the same numbers)."""
    key = tuple(float(t) for t in taus)
    b = _BASES.get(key)
    if b is None or b.shape[0] < n:
        i = np.arange(n, dtype=float)[:, None]
        t = np.asarray(key, float)
        b = np.exp(-i / t[None, :]) if t.size else np.zeros((n, 0))
        b.flags.writeable = False
        if key not in _BASES and len(_BASES) >= BASES_KEPT:
            _BASES.clear()
        _BASES[key] = b
    return b[:n]


# start_basis's bases, by taus: a diagnosis uses a few sets (the record's
# and its exploration copy's, a few burns), each at most a few MB
_BASES: dict = {}
BASES_KEPT = 8


def _fixed_regressors(pb: Problem, parts: list):
    """The regressors that do not depend on the parameters (the constant,
    when pc0 is solved, then the start's basis), whitened over the parts:
    their orthonormal basis Q and triangular factor R, the whitened output
    with pc0 (when given) removed, and that output less its projection on
    Q. Cached: they are the same for every evaluation of a problem."""
    taus = start_taus(pb)
    key = (id(pb.y), pb.y.size, tuple((x.start, x.stop) for x in parts), pb.pc0,
           _nm_key(pb), taus)
    hit = _CONSTANTS.get(key)
    if hit is not None and hit[0] is pb.y:
        return hit[1]
    end = parts[-1].stop if parts else 0
    yw = noise.whiten_parts(pb.nm, pb.y - (pb.pc0 if pb.pc0 is not None else 0.0), parts)
    cols = [start_basis(taus, end)]
    if pb.pc0 is None:
        cols.insert(0, np.ones((end, 1)))
    F = np.hstack(cols)
    if F.shape[1]:
        Q, R = np.linalg.qr(noise.whiten_parts(pb.nm, F, parts))
    else:
        Q, R = np.zeros((yw.size, 0)), np.zeros((0, 0))
    out = (Q, R, yw, yw - Q @ (Q.T @ yw))
    for a in out:            # shared by every evaluation: read only
        a.flags.writeable = False
    _remember(key, pb.y, out)
    return out


def project(pb: Problem, s: np.ndarray, solve_K: bool, K: float, parts: list):
    """(K, c, a): the gain (when solved), the output offset (when not
    given) and the start's free-response coefficients a (an empty array
    when the record opens at rest) that fit y ~ K s + c + B a over the
    parts (slices), in the whitened criterion when there is a noise model;
    K must be positive."""
    if not pb.open_start:
        K, c = _project_rest(pb, s, solve_K, K, parts)
        return K, c, np.zeros(0)
    Q, R, yw, yp = _fixed_regressors(pb, parts)
    sw = noise.whiten_parts(pb.nm, s, parts)
    if solve_K:
        sp = sw - Q @ (Q.T @ sw)
        den = float(sp @ sp)
        K = float(sp @ yp) / den if den > 1e-12 * float(sw @ sw) and den > 0 else math.nan
        rest = yw - (K * sw if math.isfinite(K) else 0.0)
    else:
        rest = yw - sw                   # s already carries K
    coef = np.linalg.solve(R, Q.T @ rest) if R.size else np.zeros(0)
    if pb.pc0 is not None:
        return K, pb.pc0, coef
    return K, float(coef[0]), coef[1:]


def _project_rest(pb: Problem, s: np.ndarray, solve_K: bool, K: float, parts: list):
    """project() for a record that opens at rest: K and c only."""
    def w(x):
        return noise.whiten_parts(pb.nm, x, parts)
    y = pb.y[:s.size]
    if pb.pc0 is not None:
        c = pb.pc0
        if solve_K:
            a, b = w(s), w(y - c)
            den = float(a @ a)
            K = float(a @ b) / den if den > 0 else math.nan
        return K, c
    one = np.ones_like(s)
    if not solve_K:
        a, b = w(one), w(y - K * s)
        den = float(a @ a)
        return K, (float(a @ b) / den if den > 0 else
                   float(np.mean(noise.whiten_parts(None, y - K * s, parts))))
    return solve2(w(s), w(one), w(y))


def _nm_key(pb: Problem):
    return None if pb.nm is None else pb.nm.a.tobytes()


def _remember(key, y, value) -> None:
    """Cache a problem's constant regressors (keyed by its output array,
    held so that its id is not reused; a few problems at a time)."""
    if len(_CONSTANTS) > 16:
        _CONSTANTS.clear()
    _CONSTANTS[key] = (y, value)


def solve2(a: np.ndarray, b: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(k, c) minimising |y - k a - c b| (the 2x2 normal equations; k NaN
    when a and b are collinear)."""
    aa, ab, bb = float(a @ a), float(a @ b), float(b @ b)
    ay, by = float(a @ y), float(b @ y)
    det = aa * bb - ab * ab
    if not det > 1e-12 * max(aa * bb, 1e-300):
        return math.nan, (by / bb if bb > 0 else 0.0)
    return (ay * bb - by * ab) / det, (aa * by - ab * ay) / det


def offset(pb: Problem, fr, n: int | None = None) -> np.ndarray | float:
    """What a fit adds to its simulated output: the offset pc0, plus the
    start's free response when the record does not open at rest (over the
    first n samples; default the whole record)."""
    a = fr.start_coef
    if a is None or not len(a):
        return fr.values["pc0"]
    n = pb.y.size if n is None else n
    return fr.values["pc0"] + start_basis(fr.start_taus, n) @ a


def model_output(pb: Problem, effects, vals: dict, dead: int = 0, n: int | None = None,
                 parts: list | None = None, oversample: int | None = None):
    """Absolute model output over the first n samples, with K, pc0 and the
    start's free response solved on the parts (default: the fit parts).
    Returns (out, K, c, a)."""
    sK = solves_K(pb, effects)
    v = dict(vals)
    if sK:
        v["K"] = 1.0
    s = simulate_raw(pb, effects, v, dead, n, oversample)
    if sK:
        K, c, a = project(pb, s, True, 1.0, parts or pb.fit_parts)
        out = K * s + c
    else:
        K, c, a = project(pb, s, False, 1.0, parts or pb.fit_parts)   # s already carries K
        out = s + c
        K = _groups(pb, vals)["K"]
    if a.size:
        out = out + start_basis(start_taus(pb), s.size) @ a
    return out, K, c, a


# ------------------------------------------------------------------ fitting
class _Objective:
    """Residual over the counted fit samples, scaled by sd(y); keeps the
    best point seen and counts simulations against a budget."""

    def __init__(self, pb, sp, effects, dead, budget, memo=None, trail=None):
        self.pb, self.sp, self.effects, self.dead = pb, sp, effects, dead
        self.budget, self.calls = budget, 0
        yw = pb.fit_white(pb.y)
        self.scale = max(float(np.std(yw)), 1e-300)
        self.best = (math.inf, None, None)   # cost, point, its model_output
        self.n = yw.size
        # Residuals at points an earlier fit of the same problem, effects
        # and dead time already evaluated (lm_fit's memo), and this fit's
        # last Jacobian's points (its base and columns), for the next. Keyed
        # by the parameter values simulated (from_theta's), on which alone
        # the residual depends: a fit restarted from another's values gets
        # its point back through log and exp, which can move the last bit
        # of theta but not of the values.
        self.memo = memo if memo is not None else {}
        self.last = {}
        # Jacobians at half the rate (_coarse_differences) while allowed:
        # where the rate halves exactly, dead time included (the library
        # rounds a delay to whole samples of the rate it runs at: an odd
        # delay at half the rate would be another delay, and the Jacobian
        # another model's), until the search's steps save little (jac),
        # the half rate's model is refused, or the search has stopped once
        # (lm_fit). The cost at the last Jacobian's point, and whether it
        # was made so.
        m = pb.setup.oversample
        self.coarse = COARSE_DEVIANCE > 0 and m % 2 == 0 and dead % 2 == 0
        self.J_cost = None
        self.J_coarse = False
        # Every point this fit evaluates, when asked (lm_fit's trail): for
        # another fit that starts where this one did (candidates._apart)
        self.trail = trail

    def __call__(self, th):
        self.calls += 1
        if self.calls > self.budget:
            raise _Budget()
        return self.eval(th)

    def eval(self, th):
        return self.keyed(th)[1]

    def keyed(self, th):
        """(the memo's key of th, the residual there), th noted as the best
        point if it is."""
        key, r, mo = self._point(th)
        self._note(th, r, mo)
        if self.trail is not None:
            self.trail[key] = r
        return key, r

    def _point(self, th):
        """(the memo's key of th, the residual there, model_output's answer
        or None); a point the memo holds is not simulated again (the same
        problem, model and values: the same numbers). Reads only: safe on
        the pool's threads."""
        vals = from_theta(self.sp, th, self.pb)
        key = tuple(vals.values())
        r = self.memo.get(key)
        mo = None
        if r is None:
            r, mo = self._residual(vals)
            r.flags.writeable = False    # shared by the memo and the Jacobian's base
        return key, r, mo

    def _note(self, th, r, mo):
        """Keep th if it is the best point so far. Called in one thread, in
        the order the points were asked for, so that the best point (and so
        the fit, and the cache's copy of it) does not depend on which
        thread of the pool finished first."""
        cst = float(r @ r)
        if cst < self.best[0]:
            self.best = (cst, np.array(th, copy=True), mo)

    def _residual(self, vals, oversample: int | None = None):
        """(the residual at these values, model_output's answer there or
        None where the library refused it or K came out unusable);
        simulated at oversample x the data rate (default: the problem's)."""
        pb = self.pb
        mo = None
        try:
            mo = model_output(pb, self.effects, vals, self.dead, pb.nsim, oversample=oversample)
            out, K = mo[0], mo[1]
            r = pb.fit_white(out - pb.y[:out.size]) / self.scale
            ok = math.isfinite(K) and K > 0
        except lib.ModelError:
            ok = False
        if not ok:
            r, mo = np.full(self.n, 1e3), None
        if not math.isfinite(float(r @ r)):
            r, mo = np.full(self.n, 1e3), None
        return r, mo

    def jac(self, th, f0=None):
        """Forward differences, one column per thread: of the model at half
        the simulation rate while the search still makes headway
        (_coarse_differences), else of the residual itself."""
        th = np.asarray(th, float)
        if f0 is None:
            f0 = self(th)
        # The first Jacobian is the residual's own: a fit that starts at
        # or near an optimum (a refinement, a confirmation, a continued
        # stage of the halving, whose last Jacobian the memo holds) is
        # decided by it, as before. After it, half the rate while the last
        # step saved more than COARSE_DEVIANCE in deviance (n ln of the
        # cost ratio; a guard resolves nothing under a BIC change of 10):
        # the search is then far from where it stops. From the first step
        # that saves less, and to the end, the residual's own again: near
        # its end the Jacobian decides where the search stops (its
        # gradient test and its last steps).
        half = False
        c = float(f0 @ f0)
        if self.coarse and self.J_cost is not None:
            c_prev = self.J_cost
            half = c > 0 and self.n * math.log(c_prev / c) > COARSE_DEVIANCE
            self.coarse = half
        self.J_cost = c
        J = self._coarse_differences(th) if half else None
        self.J_coarse = J is not None
        if J is not None:        # its base point, for a fit continued from here
            self.last = {tuple(from_theta(self.sp, th, self.pb).values()): f0}
            return J
        cols = self._steps(th)
        self.calls += len(cols)
        if self.calls > self.budget:
            raise _Budget()
        made = list(_pool.map(self._point, [t for t, _ in cols])) if _pool is not None else \
            [self._point(t) for t, _ in cols]
        for (t, _), (_, r, mo) in zip(cols, made):
            self._note(t, r, mo)
        kr = [(key, r) for key, r, _ in made]
        if self.trail is not None:
            self.trail.update(kr)
        self.last = {tuple(from_theta(self.sp, th, self.pb).values()): f0}
        self.last.update(kr)
        res = [(r - f0) / h for (_, r), (_, h) in zip(kr, cols)]
        return np.column_stack(res) if res else np.zeros((f0.size, 0))

    def _coarse_differences(self, th):
        """The Jacobian by forward differences at th of the model simulated
        at half the simulation rate (still at least the data rate: the
        oversample is 2 or more), its base point included; None where the
        library refuses one of its points. A diagnosis's simulated steps
        are mostly finite-difference Jacobians (85 % on a pid record of
        100 000 samples, docs/analysis-bench.md, branch speedproto35), and
        a Jacobian only steers the search: the fit's cost, its best point
        and (jac, lm_fit) its stop are the residual's at the full rate. The
        model at half the rate has the same groups and effects and differs
        in the discretisation of its fastest modes only, so its
        sensitivities are the full-rate model's to within that; p + 1
        simulations of half the steps cost about (p + 1) / 2p of the p full
        ones. Its points are not kept (memo, trail, best): they are another
        model's residuals. Counted against the budget as the p full
        simulations they stand in for, so that a budget ends a search after
        as many iterations as before. Only where the oversample is even and
        the dead time a whole number of half-rate samples (_Objective)."""
        cols = self._steps(th)
        self.calls += len(cols)
        if self.calls > self.budget:
            raise _Budget()
        m = self.pb.setup.oversample // 2          # even: see _Objective

        def at(t):
            return self._residual(from_theta(self.sp, t, self.pb), m)
        pts = [th] + [t for t, _ in cols]
        got = list(_pool.map(at, pts)) if _pool is not None else [at(t) for t in pts]
        if any(mo is None for _, mo in got):
            # the half rate's model refused where the full rate's was not:
            # the full rate's differences, counted once, for the rest of
            # the fit
            self.calls -= len(cols)
            self.coarse = False
            return None
        f0 = got[0][0]
        res = [(r - f0) / h for (r, _), (_, h) in zip(got[1:], cols)]
        return np.column_stack(res) if res else np.zeros((f0.size, 0))

    def _steps(self, th):
        """Each parameter's difference step at th: (the point, the step),
        taken backwards where forwards would leave the bounds."""
        lo, hi = bounds(self.sp)
        cols = []
        for i in range(th.size):
            h = DIFF_STEP * max(1.0, abs(th[i]))
            if th[i] + h > hi[i]:
                h = -h
            t = th.copy()
            t[i] += h
            cols.append((t, h))
        return cols


def lm_fit(pb: Problem, effects, start: dict, dead: int = 0, budget: int = 400,
           label: str = "", ftol: float = 1e-5, memo: dict | None = None,
           trail: dict | None = None) -> FitResult:
    """Least squares from one start; returns the best point visited. The
    default ftol (relative cost change per step) of 1e-5 is far below what
    the guards resolve (a BIC change of 10 is 10/n of the cost: 1.4e-4 at
    70 000 samples) and stops the search crawling along flat ridges.
    memo: residuals (keyed by the values simulated: _Objective) that
    earlier fits of this same problem object, effects and dead time
    evaluated; read, and this fit's last Jacobian's points added. A fit continued from where another
    stopped (search._halving's stages) starts with the Jacobian the other
    ended with, at the same point: its p + 1 simulations are not made
    again (the budget counts them as before, so the search is the same).
    trail: a dict to which every point this fit evaluates is added (keyed
    as memo): given as memo to a fit of the same problem, effects and dead
    time from the same start with a larger budget, that fit follows this
    one's path evaluation for evaluation (least_squares is deterministic,
    and the budget and max_nfev only stop it: _answers), so the points this
    one made are not simulated again; only the memo's numbers, the same."""
    effects = model.canonical(effects)
    sp = specs(pb, effects)
    th0 = to_theta(sp, start, pb)
    lo, hi = bounds(sp)
    th0 = np.clip(th0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
    key = _fit_key(pb, effects, th0, dead, ftol)
    max_nfev = _max_nfev(budget, th0.size)
    with _FITS_LOCK:
        hit = _answers(key, budget, max_nfev)
        if hit is not None:
            _FITS.move_to_end(hit)
            hit = copy.deepcopy(_FITS[hit][2])
    if hit is not None:        # (its last Jacobian is not in memo: a little speed only)
        hit.start = label
        return hit
    obj = _Objective(pb, sp, effects, dead, budget, memo, trail)
    state = {}

    def fun(th):
        r = obj(th)
        state["x"], state["f"] = np.array(th, copy=True), r
        return r

    def jac(th):
        f0 = state["f"] if "x" in state and np.array_equal(state["x"], th) else None
        return obj.jac(th, f0)

    status, nfev = "budget", 0
    if th0.size:
        try:
            x = th0
            while True:
                status = "budget"        # until this run returns
                res = least_squares(fun, x, jac=jac, bounds=(lo, hi), method="trf",
                                    x_scale="jac", xtol=1e-6, ftol=ftol, gtol=1e-8,
                                    max_nfev=max_nfev - nfev)
                status, nfev = f"{res.status}", nfev + res.nfev
                # A stop at a tolerance judged on a Jacobian made at half
                # the rate (_Objective._coarse_differences: the search
                # stopped while its steps still saved much) is not taken as
                # convergence: that Jacobian is another model's, and the
                # stop can lie short of this model's optimum. The search
                # goes on from the best point with the residual's own, to
                # its stop (or max_nfev's, or the budget's).
                if res.status <= 0 or not obj.J_coarse:
                    break
                if nfev >= max_nfev:     # stopped short, and nothing left to go on with
                    status = "0"
                    break
                x, obj.coarse, obj.J_coarse = obj.best[1], False, False
                state.clear()
        except _Budget:
            pass
    if _TRACE:
        import sys
        print(f"[lm] {label:14s} {'+'.join(effects) or 'none':18s} n={pb.n_counted} p={th0.size} "
              f"sims={obj.calls} status={status} cost {obj.best[0]:.6g}", file=sys.stderr)
    if not th0.size:             # nothing to search: the start is the answer
        obj.eval(th0)
    if memo is not None:
        memo.update(obj.last)
    c, th, mo = obj.best
    if th is None:
        th = th0
    fr = finish(pb, effects, sp, th, dead, c * obj.scale ** 2, label, mo)
    # converged: stopped by a tolerance (least_squares' status 1-4), or
    # nothing to search; not by max_nfev (0) or the budget (_Budget)
    converged = not th0.size or status in ("1", "2", "3", "4")
    reach = (obj.calls, nfev) if converged else None
    with _FITS_LOCK:
        _FITS[(key, int(budget))] = (int(budget), reach, copy.deepcopy(fr))
        _FITS.move_to_end((key, int(budget)))
        while len(_FITS) > FITS_KEPT:
            _FITS.popitem(last=False)
    return fr


def _max_nfev(budget: int, p: int) -> int:
    """least_squares' max_nfev for a budget of simulations and p
    parameters: each iteration costs a Jacobian (p simulations) and at
    least one residual."""
    return max(budget // max(p + 1, 1), 3)


# Whole fits repeated: a search makes some fits twice, from the same start
# on the same data with the same budget (a reference and its confirmation
# explore the same starts, each on its own exploration copy of the record).
# lm_fit's answer depends on its arguments, the problem's content and the
# package's settings alone, so a repeat gets a copy of the first (a few kB
# each, before evaluate adds the whole-record output). Keyed by a digest
# of the problem's values, of the arguments but the budget, and of the
# settings (_fit_key), and by the budget: an entry is (budget, reach, fit),
# reach the simulations and least_squares' evaluations a converged run
# made (None where the budget stopped it), which says which other budgets
# it answers (_answers). Entries of several budgets under one key are kept
# side by side, so a fit made with one budget does not drop another's. A
# lock, as a thread's hit could otherwise meet another's eviction.
_FITS: OrderedDict = OrderedDict()
_FITS_LOCK = threading.Lock()
FITS_KEPT = 64


def _fit_key(pb: Problem, effects, th0, dead: int, ftol: float) -> bytes:
    """What an lm_fit's answer depends on, but its budget (_answers): the
    problem's values, the arguments (digest.of: the same in a forked worker
    as in its parent), and the settings of the package's modules
    (digest.settings: iteration counts, tolerances, DIFF_STEP,
    model.F_SIM_MIN, the groups' ranges...), so that a setting changed at
    run time is not answered with a fit made under the old one."""
    return digest.of(pb, tuple(effects), th0, int(dead), float(ftol),
                     digest.settings(__package__))


def _answers(key: bytes, budget: int, max_nfev: int):
    """The key in _FITS of the fit that lm_fit with `budget` (and
    least_squares' max_nfev) returns, or None; under _FITS_LOCK. That is
    the fit made with the same budget; or one that converged, with any
    budget, whose run fits in this one: its simulations (_Objective's
    count) within `budget` and least_squares' evaluations within
    `max_nfev`. The budget only stops the search. In scipy's trf (read in
    scipy 1.17.1's _lsq/trf.py, trf_bounds), max_nfev is tested only at
    the loop's top, after the tolerance tests, and in the inner loop's
    `nfev < max_nfev`; x_scale='jac' and the 'exact' solver read J alone.
    So a run that stopped at a tolerance after N evaluations made each of
    them with fewer than N before it: any max_nfev >= N lets the same
    evaluations through to the same stop, and any budget >= its
    simulations never stops it (_Objective raises only past the budget).
    A larger budget than a converged fit's is always such a one (a
    confirmation refines the better model so far with twice the
    iterations its reference did: selection.confirm); a smaller one is
    where the run needed less than it allowed."""
    if (key, budget) in _FITS:
        return (key, budget)
    # A scan of every entry, not an index by key: _FITS holds at most
    # FITS_KEPT (64) entries, so a miss compares 64 digests (bytes), nothing
    # against the fit (thousands of simulations) the answer saves or the
    # miss then runs.
    for k, (_, reach, _) in reversed(_FITS.items()):
        if k[0] == key and reach is not None and reach[0] <= budget and reach[1] <= max_nfev:
            return k
    return None


def finish(pb: Problem, effects, sp, th, dead: int, cost: float, label: str = "",
           made=None) -> FitResult:
    """The fit at th. made: model_output's answer at th when the search
    already simulated it (the placement it simulated is pb's, which the
    values name below: the same run)."""
    vals = from_theta(sp, th, pb)
    if "saturation" in effects:          # the placement simulated (candidates.with_kind)
        vals.update(sat_kind=pb.setup.sat_kind, sat_kind_told=pb.setup.sat_kind_told)
    out, K, c, a = made if made is not None else model_output(pb, effects, vals, dead, pb.nsim)
    vals["K"] = K
    vals["pc0"] = c
    g = _groups(pb, vals)
    g["K"] = K
    sK = solves_K(pb, effects)
    # The start's terms are not counted: every model of a record has them,
    # and where one comparison discounts a longer start (a dead band) fewer
    # of them reach its samples, which is no simpler model.
    k = len(sp) + (1 if sK else 0) + (1 if pb.pc0 is None else 0) + (1 if "dead_time" in effects else 0)
    fr = FitResult(effects, g, vals, [s[0] for s in sp], np.asarray(th, float), cost, dead, k,
                   sK, pb.pc0 is None, start=label,
                   free_groups=[x for x in pb.free if x in model.GROUPS or x == "e0"],
                   start_coef=a, start_taus=start_taus(pb))
    return fr


def evaluate(pb: Problem, fr: FitResult) -> None:
    """Whole-record simulation (K and pc0 from the fit part), NRMSE on the
    fit and held-out parts, BIC on the counted fit samples."""
    v = dict(fr.values)
    if fr.K_solved:
        v["K"] = 1.0
        fr.sim = fr.values["K"] * simulate_raw(pb, fr.effects, v, fr.dead) + offset(pb, fr)
    else:
        fr.sim = simulate_raw(pb, fr.effects, v, fr.dead) + offset(pb, fr)
    r = pb.y - fr.sim
    fr.nrmse_fit = nrmse(pb.fit_of(r), pb.fit_of(pb.y))
    fr.nrmse_val = nrmse(pb.held_of(r), pb.held_of(pb.y))
    rc = pb.fit_white(r)
    rss = float(rc @ rc)
    m = rc.size
    fr.cost = rss
    fr.bic = m * math.log(max(rss, 1e-300) / m) + fr.k * math.log(m)


def nrmse(r, y) -> float:
    d = float(np.sqrt(np.mean((y - np.mean(y)) ** 2)))
    return float(np.sqrt(np.mean(r * r))) / d if d > 0 else math.inf


# ------------------------------------------------------------- uncertainty
def full_specs(pb: Problem, fr: FitResult):
    """The search's parameters plus the solved ones (log K, pc0), for the
    Jacobian of intervals."""
    sp = list(specs(pb, fr.effects))
    if fr.K_solved:
        sp.append(("K", "log", 1e-300, 1e300))
    if fr.pc0_solved:
        sp.append(("pc0", "lin", -1e300, 1e300))
    return sp


def jacobian(pb: Problem, fr: FitResult) -> tuple[list, np.ndarray]:
    """d model output / d parameter (transformed) over the samples the fit
    simulates (rows: samples 0..nsim-1), K and pc0 included as plain
    parameters."""
    sp = full_specs(pb, fr)
    th = to_theta(sp, fr.values, pb)

    def out(t):
        v = from_theta(sp, t, pb)
        K = v.get("K", fr.values["K"])
        c = v.get("pc0", fr.values["pc0"])
        if solves_K(pb, fr.effects):
            vv = dict(v)
            vv["K"] = 1.0
            s = simulate_raw(pb, fr.effects, vv, fr.dead, pb.nsim)
            return K * s + c
        return simulate_raw(pb, fr.effects, v, fr.dead, pb.nsim) + c

    f0 = out(th)
    lo, hi = bounds(sp)

    def col(i):
        """Forward difference, backward at an upper bound or where the
        library refuses the forward point; 0 where it refuses both."""
        h = DIFF_STEP * max(1.0, abs(th[i]))
        for step in ((h, -h) if th[i] + h <= hi[i] else (-h,)):
            t = th.copy()
            t[i] += step
            try:
                return (out(t) - f0) / step
            except lib.ModelError:
                continue
        return np.zeros_like(f0)

    idx = range(th.size)
    res = list(_pool.map(col, idx)) if _pool is not None else [col(i) for i in idx]
    return sp, np.column_stack(res)


def _without(J: np.ndarray, B: np.ndarray) -> np.ndarray:
    """J's columns less their least-squares fit by B's columns."""
    if not B.shape[1]:
        return J
    return J - B @ np.linalg.lstsq(B, J, rcond=None)[0]


def uncertainty(pb: Problem, fr: FitResult, noise_model=noise.fit_arfima) -> None:
    """Standard errors and 95 % intervals of every parameter (transformed
    coordinates): the sandwich covariance of the estimate, with the noise
    modelled from its (whitened, when the criterion is) residual by
    noise_model: by default ARFIMA(p, d, 0) (noise.fit_arfima: under 1/f or
    long-memory noise an AR model alone understates the power the fit's slow
    directions absorbed); noise.fit for the AR model alone. It holds whether
    or not the criterion's own noise model is right."""
    sp, J = jacobian(pb, fr)
    # The start's coefficients are parameters too (nuisance ones): by Frisch
    # and Waugh, the other parameters' covariance is that of their Jacobian
    # with the part the start's basis reproduces removed.
    B = start_basis(start_taus(pb), pb.nsim)
    fr.jac = _without(pb.fit_of(J), pb.fit_of(B))
    r = fr.residual(pb)
    Jw = pb.fit_white(J)
    rw = pb.fit_white(r)
    fr.noise = noise_model(rw)
    cov = noise.sandwich(_without(Jw, pb.fit_white(B)) if B.shape[1] else Jw, fr.noise)
    se = np.sqrt(np.clip(np.diag(cov), 0, np.inf))
    th = to_theta(sp, fr.values, pb)
    fr.se, fr.ci = {}, {}
    for (name, tr, lo, hi), t, s in zip(sp, th, se):
        if tr == "wnu":
            nu = _nu(pb, fr.values)
            s = (1.0 - nu) * s if math.isfinite(s) else s    # dw = (1 - nu) ds
            fr.se[name] = float(s)
            w = w_from_s(nu, t)
            fr.ci[name] = ((None, None) if not math.isfinite(s) else
                           (float(max(nu, w - 1.96 * s)), float(min(1.0, w + 1.96 * s))))
            continue
        fr.se[name] = float(s)
        if not math.isfinite(s) or (tr == "log" and 1.96 * s > 600):
            fr.ci[name] = (None, None)
        elif tr == "log":
            fr.ci[name] = (math.exp(t - 1.96 * s), math.exp(t + 1.96 * s))
        else:
            fr.ci[name] = (t - 1.96 * s, t + 1.96 * s)


def uncertainty_later(pb: Problem, fr: FitResult) -> None:
    """uncertainty(pb, fr) when fr's intervals are first needed (settle),
    not now. A round fits every candidate, and the intervals of a
    candidate's fit decide nothing (the guards take the profile
    likelihood's test, guards.test: the Wald interval there is not read):
    they are reported only for the model the selection ends with
    (diagnose: the extended model's ci95). Made once at the end, on the
    problem and fit this call was given (neither is changed in between:
    a fit is not edited once found), they are the same numbers; made for
    every candidate of every round they cost about a tenth of a diagnosis
    (docs/analysis-bench.md, branch speed32)."""
    fr.owed = pb


def settle(fr: FitResult, pb: Problem, noise_model=noise.fit_arfima) -> None:
    """fr's intervals, as a report needs them: those uncertainty_later owes
    fr, made now on the problem it was given; made on pb (by noise_model)
    if fr has none at all (a model refitted after the rounds, as backward's
    drop or a baseline found in round 1, was never asked for them); else
    nothing (made already)."""
    if fr is None:
        return
    if fr.owed is not None:
        owed, fr.owed = fr.owed, None
        uncertainty(owed, fr)
    elif not fr.ci:
        uncertainty(pb, fr, noise_model)


def transform_of(name: str) -> str:
    if name in ("lag", "K") or (name in model.GROUPS and model.GROUPS[name][0] == "log"):
        return "log"
    return "lin"


# ------------------------------------------------------------ start points
def random_starts(pb: Problem, rng: np.random.Generator, m: int) -> list[dict]:
    """Fresh starts spread over the plausible ranges (log-uniform for time
    constants and gains); K and pc0 are solved."""
    fs, T = pb.setup.fs, pb.setup.duration
    nom = model.nominal_groups(pb.setup.config)
    out = []
    for _ in range(m):
        g = {}
        for name in pb.free:
            if name == "K":
                g[name] = 1.0
            elif name == "e0":
                g[name] = pb.e0_default()
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


def start_cost(pb: Problem, effects, vals: dict, dead: int = 0) -> float:
    """RSS of a start over the counted fit samples (K, pc0 solved where they
    can be): how fresh starts are ranked."""
    try:
        out, K, _, _ = model_output(pb, effects, vals, dead, pb.nsim)
    except lib.ModelError:
        return math.inf
    if not (math.isfinite(K) and K > 0):
        return math.inf
    r = pb.fit_white(out - pb.y[:out.size])
    c = float(r @ r)
    return c if math.isfinite(c) else math.inf
