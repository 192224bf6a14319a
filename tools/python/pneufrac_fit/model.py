# SPDX-License-Identifier: MIT
"""Identifiable parameterisation of the paper's controllers, and the effects.

Only groups reach the output. With ce = b/(a+b), cy = a/(a+b), kA = A/ks
and R~(s) = (1+(tau s)^beta)/(1+rho (tau s)^beta), every configuration is

    P_c/E = K R~ / (1 + L R~ s^-q M(s)),    M = 1, Rv, 1-Rw, Rv-Rw

    K   = ce k1 k2 / pmin      forward gain, output units per input unit
    L   = cy k1 k2 kA / pmin   loop gain (dimensionless with s in 1/s)
    rho = pmax / pmin          relay stiffness ratio (>= 1)
    tau, beta                  relay diaphragm (eq. 11)
    q                          bellows order (eq. 16)
    RC, nu / w (RCd, RCi)      restrictors

k1 and k2 only act as a product, and a, b, A, ks, pmin only through these
groups, so the fit never sees them separately. A group vector maps back to
one physical parameter set (a = 1, b = 9, k1 = ks = pmin = 1) that the
library simulates. Backlash and the nozzle curve act on the flapper
displacement x = ce (e - (cy/ce) y); the fit states them in input units
(x / ce), which is what the data determine whatever a and b are.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from . import data, lib, placement_share, timebase

CE, CY = 0.9, 0.1          # lever ratios of the fixed mapping (a = 1, b = 9)

# The bound a group takes from the library's parameter table
# (pf_param_info), where the group is one of the library's parameters.
LIB = "library"

# name: (transform, lower, upper, meaning); lower/upper None: a time
# constant, bounded by the record (Setup.bounds)
GROUPS = {
    "K": ("log", 1e-9, 1e9, "forward gain b/(a+b)·k1·k2/Ψmin (output per input unit)"),
    "L": ("log", 1e-8, 1e4, "loop gain a/(a+b)·k1·k2·(A/ks)/Ψmin"),
    "tau": ("log", None, None, "relay time constant τ (s)"),
    "rho": ("log", 1.0, 1e4, "relay stiffness ratio Ψmax/Ψmin"),
    "beta": ("lin", 0.05, LIB, "relay diaphragm order β"),
    "q": ("lin", LIB, LIB, "bellows order q"),
    "RC": ("log", None, None, "restrictor time constant RC (s)"),
    "nu": ("lin", 0.05, LIB, "derivative restrictor order ν"),
    "w": ("lin", 0.05, LIB, "reset restrictor order w"),
    "RCd": ("log", None, None, "derivative restrictor RCd (s)"),
    "RCi_ratio": ("log", 1.0 + 1e-6, 1e6, "RCi/RCd"),
}

CONFIG_GROUPS = {
    "p": ["K", "L", "tau", "rho", "beta", "q"],
    "dd": ["K", "L", "tau", "rho", "beta", "q", "RC", "nu"],
    "id": ["K", "L", "tau", "rho", "beta", "q", "RC", "w"],
    "pid": ["K", "L", "tau", "rho", "beta", "q", "RCd", "RCi_ratio", "nu", "w"],
}

# Effect parameters in the units the report uses.
EFFECT_PARAMS = {
    "dead_time": ["dead_time"],          # s (whole internal samples)
    "lag": ["lag"],                      # s
    # output units; where the limits act (SAT_KINDS) and whether the
    # record tells that placement from the other (1) or not (0)
    "saturation": ["sat_lo", "sat_hi", "sat_kind", "sat_kind_told"],
    "backlash": ["deadband"],            # full width, input units
    "nozzle": ["nozzle_xh", "nozzle_bias"],  # x_1/2, input units; bias point
    "none": [],
}
CAUSES = ["dead_time", "lag", "saturation", "backlash", "nozzle"]


def canonical(effects) -> tuple:
    """A set of effects in the catalogue's order (one name for one model)."""
    s = set(effects)
    return tuple(c for c in CAUSES if c in s)


PLACE = {
    "dead_time": "output line (transport delay)",
    "lag": "output line (extra first-order lag of the line volume)",
    "saturation": "relay output p_c, inside the loop (supply limits)",
    "backlash": "flapper displacement x, inside the loop (play / dead band)",
    "nozzle": "flapper displacement x, inside the loop (nozzle characteristic)",
    "none": "-",
}


# Where the supply limits act (the library's pf_sat_kind): all are fitted
# and the best kept (candidates.fit_extended); the report says which.
SAT_CLIP, SAT_STOP, SAT_WIND = lib.PF_SAT_CLIP, lib.PF_SAT_STOP, lib.PF_SAT_WIND
SAT_KINDS = {
    SAT_CLIP: "the output pressure is clipped (p_c limited after the relay, whose "
              "memory runs on)",
    SAT_STOP: "the relay reaches its stop (the diaphragm sits on its seat; its memory "
              "holds the stopped position)",
    SAT_WIND: "the relay's output stops and its memory winds on (the diaphragm stays "
              "loaded by the whole p_b: a delayed recovery, longer than the clip's)",
}


def sat_kind(vals: dict, default: int = SAT_CLIP) -> int:
    """The saturation placement a fit's values carry (default: clip)."""
    k = int(vals.get("sat_kind", default))
    return k if k in SAT_KINDS else default


def group_bounds(name: str) -> tuple[float | None, float | None]:
    """A group's fixed bounds: its own, or the library's range where the
    group is a library parameter (LIB); (None, None) for time constants."""
    _, lo, hi, _ = GROUPS[name]
    if LIB in (lo, hi):
        r = lib.param_range(name)
        lo = r.lo if lo == LIB else lo
        hi = r.hi if hi == LIB else hi
    return lo, hi


def groups_from_physical(config: str, p: dict) -> dict:
    """Group values of a physical parameter set (paper names)."""
    ce = p["b"] / (p["a"] + p["b"])
    cy = p["a"] / (p["a"] + p["b"])
    g = {
        "K": ce * p["k1"] * p["k2"] / p["pmin"],
        "L": cy * p["k1"] * p["k2"] * (p["A"] / p["ks"]) / p["pmin"],
        "tau": p["tau"], "rho": p["pmax"] / p["pmin"], "beta": p["beta"],
        "q": p["q"],
    }
    for name in ("nu", "w", "RC"):
        if _param_used(config, name):
            g[name] = p[name]
    if config == "pid":
        g["RCd"] = p["RCd"]
        g["RCi_ratio"] = p["RCi"] / p["RCd"]
    return g


def nominal_groups(config: str) -> dict:
    """The paper's example values (pf_params_default) as groups."""
    return groups_from_physical(config, lib.default_params(config))


# Whether a configuration uses a parameter: the library's fixed table, asked
# three times for every simulation (physical_from_groups) at a few
# microseconds each through ctypes (about 1 % of a diagnosis, branch
# speed32); kept per (configuration, name), the answer the table gives.
_param_used = functools.lru_cache(maxsize=None)(lib.param_used)


def physical_from_groups(config: str, g: dict) -> dict:
    k1 = 1.0
    k2 = g["K"] / (CE * k1)
    kA = g["L"] / (CY * k1 * k2)
    p = {"a": 1.0, "b": 9.0, "k1": k1, "k2": k2, "A": kA, "ks": 1.0,
         "tau": g["tau"], "pmin": 1.0, "pmax": g["rho"], "beta": g["beta"],
         "q": g["q"]}
    for name in ("RC", "nu", "w"):
        if _param_used(config, name):
            p[name] = g[name]
    if config == "pid":
        p["RCd"] = g["RCd"]
        p["RCi"] = g["RCd"] * g["RCi_ratio"]
        # No silent clamp: the library refuses nu > w (pf_params), and the fit
        # keeps nu <= w by its parameterisation (fit.specs), so the groups
        # reported are the ones simulated.
    return p


def library_effects(effects, ev: dict, fs_int: float, kind: int = SAT_CLIP) -> dict:
    """Effect parameters (report units) of a set of effects to the
    library's pf_effects; fs_int is the simulation rate (dead time is a
    whole number of its samples, ev["dead"]); kind: the saturation's
    placement where ev does not carry one (sat_kind)."""
    fx = {}
    for eff in effects:
        if eff == "dead_time" and ev.get("dead", 0) > 0:
            fx["dead_time"] = ev["dead"] / fs_int
        elif eff == "lag":
            fx["lag"] = ev["lag"]
        elif eff == "saturation":
            fx.update(saturate=sat_kind(ev, kind), sat_lo=ev["sat_lo"], sat_hi=ev["sat_hi"])
        elif eff == "backlash" and ev["deadband"] > 0:
            fx["backlash"] = ev["deadband"] * CE
        elif eff == "nozzle" and ev.get("nozzle_k", 0) > 0:
            fx["nozzle_xh"] = CE / ev["nozzle_k"]
            fx["nozzle_bias"] = ev.get("nozzle_bias", 0.0)
    return fx


# Internal simulation rate: at least F_SIM_MIN less FS_RTOL (the data rate
# times the smallest whole factor that reaches it, within the precision of
# the rate: rate_multiple), so that a slow record is not simulated coarser
# than the 1 kHz x 2 the method was validated at.
F_SIM_MIN = 2000.0
# How far the rate a record reads can be off its clock's: timebase takes
# the period as the least-squares slope of the stamps over a gap-free
# stretch, each stamp within JITTER_TOL periods of its grid point. Over N
# stamps that slope is off by at most JITTER_TOL * sum|k - mean| /
# sum (k - mean)^2 = 3 JITTER_TOL / N periods (relative), and N is at least
# data.MIN_SAMPLES: 3 x 0.25 / 200 = 0.375 %.
FS_RTOL = 3 * timebase.JITTER_TOL / data.MIN_SAMPLES


def rate_multiple(r: float) -> float:
    """r, a ratio of a rate read off a record's time stamps to a fixed rate
    (or its inverse), as the whole number it is within the rate's
    precision (FS_RTOL of r; the nearest one where several are), else r
    itself. Wherever a rate is cut to a whole factor (the simulation's
    multiple: auto_oversample; the exploration copy's decimation:
    search.explorer) the cut goes through here, so that a record whose
    clock is a hair slow or whose stamps jitter (a 1 kHz record reads
    999.9999 Hz, a 10 kHz one 9999.999 Hz) is cut as the same record
    stamped exactly: the record cannot tell the two rates apart, and the
    next factor over costs a step a sample more (3 instead of 2 at 1 kHz)
    or makes another copy (a 10 kHz record averaged by 9, a 1111 Hz copy,
    instead of by 10)."""
    n = math.floor(r + 0.5)
    return n if n >= 1 and abs(r - n) <= r * FS_RTOL else r


def auto_oversample(fs: float) -> int:
    """The smallest whole factor that takes fs to F_SIM_MIN, within the
    rate's precision (rate_multiple): a rate that reads within FS_RTOL of
    one a whole factor takes to F_SIM_MIN gets that factor (999.9999 Hz: 2,
    as 1 kHz), and a rate really that much slower is simulated at most
    0.375 % under F_SIM_MIN. A rate whose 2000 / fs is whole keeps that
    factor (1 Hz: 2000). Below 15 Hz (a factor over 0.5 / FS_RTOL) every
    rate is within the tolerance of a whole factor and takes the nearest
    (7 Hz: 286, 2002 Hz; 7.01 Hz: 285, 1998 Hz)."""
    return max(1, math.ceil(rate_multiple(F_SIM_MIN / fs)))


@dataclass
class Setup:
    """What every simulation of one record shares."""
    config: str
    fs: float
    duration: float
    order: int = 8
    oversample: int = 1
    sat_kind: int = SAT_CLIP     # saturation's placement, where a fit's values name none
    sat_kind_told: float = 0.0   # 1: the record told it from the other placements

    def bounds(self, name: str) -> tuple[float, float]:
        lo, hi = group_bounds(name)
        if lo is None:  # time constants: from a tenth of a sample to 10 records
            lo, hi = 0.1 / self.fs, 10.0 * self.duration
        return lo, hi

    @property
    def fs_int(self) -> float:
        """The simulation rate: oversample x the data rate."""
        return self.fs * self.oversample

    def simulate(self, g: dict, e: np.ndarray, effects=(), ev: dict | None = None,
                 oversample: int | None = None, internal: bool = False) -> np.ndarray:
        """The library's output at the data samples for input e (deviation
        from the operating point), simulated at oversample x the data rate
        with the input held over each data sample (internal: every sample of
        the simulation rate)."""
        m = self.oversample if oversample is None else oversample
        p = physical_from_groups(self.config, g)
        ev = dict(ev or {})
        if oversample is not None and "dead" in ev:   # the same delay in seconds
            ev["dead"] = ev["dead"] * m / self.oversample
        fx = library_effects(effects, ev, self.fs * m, self.sat_kind)
        t_slow = max(self.duration, 1.0 / self.fs * 100)
        store, key = placement_share.active(), None
        if store is not None and fx.get("saturate"):   # shared between placements
            key = placement_share.run_key(
                e, self.config, tuple(sorted(p.items())),
                tuple(sorted((k, v) for k, v in fx.items() if k != "saturate")),
                self.fs * m, self.order, t_slow, m, internal)
            got = store.get(key, e) if key is not None else None
            if got is not None:
                return got
        ctl = lib.Controller(self.config, p, fx, self.fs * m, order=self.order, t_slow=t_slow)
        out = ctl.run(held_input(e, m))
        if m > 1 and not internal:
            out = out[::m]
        if key is not None and ctl.limited == 0:
            store.put(key, e, out)
        return out


class DerivedArrays:
    """The last few read-only arrays made from a source array, each kept
    with its source (held, so that the source's id is not reused while the
    entry lives) and keyed by the source's id and the making's arguments;
    all dropped when full. For passes over a whole record that a fit makes
    again and again with the same arguments (held_input, fit._input). The
    pool's threads may ask for the same one at once: either answer is the
    same numbers."""

    def __init__(self, kept: int):
        self.kept, self._got = kept, {}

    def get(self, src: np.ndarray, args: tuple, make) -> np.ndarray:
        key = (id(src),) + args
        hit = self._got.get(key)
        if hit is not None and hit[0] is src:
            return hit[1]
        out = make()
        out.flags.writeable = False
        if len(self._got) >= self.kept:
            self._got.clear()
        self._got[key] = (src, out)
        return out


def held_input(e: np.ndarray, m: int) -> np.ndarray:
    """e held over m samples of the simulation rate (np.repeat). The fits
    simulate the same input (fit._input's read-only array) for most points
    of a Jacobian, and the hold is a pass over m times the record: the last
    few holds of a read-only e are kept (_HELD). A writable e could change
    under the key: it is held afresh."""
    if m == 1:
        return e
    if e.flags.writeable:
        return np.repeat(e, m)
    return _HELD.get(e, (m,), lambda: np.repeat(e, m))


_HELD = DerivedArrays(4)     # each m times the size of a record


def fmt_value(name: str, v: float) -> str:
    if name in ("tau", "RC", "RCd", "lag", "dead_time"):
        return f"{v * 1e3:.4g} ms"
    return f"{v:.4g}"


def finite(v) -> float | None:
    return float(v) if v is not None and math.isfinite(v) else None
