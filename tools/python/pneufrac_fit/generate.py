# SPDX-License-Identifier: MIT
"""Synthetic bump tests with a hidden effect, for tests and examples.

The plant is the library itself (paper parameters unless overridden), with
at most one effect switched on, simulated at `oversample` times the output
rate with the library's default (high) Oustaloup order, then sampled at the
output rate; white Gaussian sensor noise is added to p_c. Effect sizes are
given in the units the diagnosis reports:

    dead_time  s                      lag        s
    backlash   dead-band full width, input units (the library gets x units)
    nozzle     x_1/2, input units
    saturation sat_lo, sat_hi, output units
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import lib, model


def bump_input(n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
               hold=(0.06, 0.4), rest: float = 0.1, min_step: float = 0.15) -> np.ndarray:
    """Random steps of varied amplitude and sign, after a rest at zero.

    Levels are uniform in [-amp, amp]; consecutive levels differ by at least
    min_step*amp, so both small and large rises and falls occur."""
    e = np.zeros(n)
    i = int(round(rest * fs))
    level = 0.0
    while i < n:
        while True:
            new = rng.uniform(-amp, amp)
            if abs(new - level) >= min_step * amp:
                break
        level = new
        k = max(1, int(round(rng.uniform(*hold) * fs)))   # fs < 1/hold: 1 sample
        e[i:i + k] = level
        i += k
    return e


@dataclass
class Dataset:
    t: np.ndarray
    e: np.ndarray
    pc: np.ndarray
    clean: np.ndarray
    fs: float
    config: str
    effect: str
    effect_params: dict
    noise_sd: float
    params: dict = field(default_factory=dict)

    @property
    def noise_floor(self) -> float:
        """NRMSE of a perfect model on the validation part (last 30 %)."""
        s = int(0.7 * self.e.size)
        return self.noise_sd / float(np.std(self.pc[s:]))

    def comments(self) -> list[str]:
        fx = ", ".join(f"{k}={v:.6g}" for k, v in self.effect_params.items()) or "-"
        return [f"pneufrac-fit generate: config={self.config} effect={self.effect} ({fx})",
                f"fs={self.fs:g} Hz, noise sd={self.noise_sd:.6g} (output units)"]


def generate(config: str = "dd", effect: str = "none", effect_params: dict | None = None,
             *, n: int = 6000, fs: float = 1000.0, noise: float = 0.005,
             oversample: int = 4, seed: int = 0, amp: float = 1.0,
             params: dict | None = None, e: np.ndarray | None = None) -> Dataset:
    """One record. noise is the sensor noise sd as a fraction of the clean
    output's span (max - min)."""
    rng = np.random.default_rng(seed)
    p = lib.default_params(config)
    p.update(params or {})
    ev = dict(effect_params or {})
    if e is None:
        e = bump_input(n, fs, rng, amp)
    fx = model.library_effects(effect, ev, fs * oversample)
    if effect in ("backlash", "nozzle"):
        ce = p["b"] / (p["a"] + p["b"])  # report units -> x units of *this* plant
        key = "backlash" if effect == "backlash" else "nozzle_xh"
        fx[key] = fx[key] / model.CE * ce
    if effect == "dead_time":
        fx["dead_time"] = ev["dead_time"]
    ctl = lib.Controller(config, p, fx, fs * oversample)
    clean = ctl.run(np.repeat(e, oversample))[::oversample]
    sd = noise * float(np.ptp(clean))
    pc = clean + sd * rng.standard_normal(clean.size)
    t = np.arange(e.size) / fs
    return Dataset(t, e, pc, clean, fs, config, effect, ev, sd, p)


def linear_output(config: str, e: np.ndarray, fs: float, oversample: int = 4,
                  params: dict | None = None) -> np.ndarray:
    """The clean output without any effect (to place saturation limits)."""
    p = lib.default_params(config)
    p.update(params or {})
    return lib.Controller(config, p, {}, fs * oversample).run(np.repeat(e, oversample))[::oversample]


def perturbed_params(config: str, rng: np.random.Generator, amount: float = 1.0) -> dict:
    """The paper's parameters with device-to-device variation (so that a
    fit which holds a group at the paper's value is not handed the truth):
    time constants x/ up to 1.4, gains and Psi_max x/ up to 1.25, orders
    +- 0.05. q = 0 (a linear spring, Example 7) stays 0."""
    p = lib.default_params(config)
    f = lambda r: float(np.exp(amount * rng.uniform(-np.log(r), np.log(r))))
    p["tau"] *= f(1.4)
    p["pmax"] = max(p["pmax"] * f(1.25), 1.5 * p["pmin"])
    p["k1"] *= f(1.25)
    for k in ("RC", "RCd", "RCi"):
        p[k] *= f(1.4)
    p["RCi"] = max(p["RCi"], 2.0 * p["RCd"])
    for k in ("beta", "nu", "w"):
        p[k] = float(np.clip(p[k] + amount * rng.uniform(-0.05, 0.05), 0.1, 1.0))
    if p["q"] > 0:
        p["q"] = float(np.clip(p["q"] + amount * rng.uniform(-0.05, 0.05), 0.05, 1.0))
    p["w"] = max(p["w"], p["nu"]) if config == "pid" else p["w"]
    return p


def draw_effect(effect: str, config: str, rng: np.random.Generator, fs: float,
                e: np.ndarray, size: float | None = None,
                params: dict | None = None) -> dict:
    """A hidden effect of a size a careful engineer could detect at 0.5 %
    noise; size in [0, 1] picks within the range (None: random)."""
    u = rng.uniform() if size is None else size
    span_e = float(np.ptp(e))
    if effect == "dead_time":
        return {"dead_time": (3.0 + 7.0 * u) / fs}            # 3..10 samples
    if effect == "lag":
        return {"lag": (4.0 + 16.0 * u) / fs}                 # 4..20 samples
    if effect == "backlash":
        return {"deadband": (0.01 + 0.04 * u) * span_e}       # 1..5 % of span
    if effect == "nozzle":
        amp = float(np.max(np.abs(e)))
        return {"nozzle_xh": (1.5 + 2.5 * u) * amp}           # 5..25 % compression
    if effect == "saturation":
        # Limits inside the range that both the fit part (first 70 %) and the
        # validation part reach, so that both see the clipping.
        y = linear_output(config, e, fs, params=params)
        s = int(0.7 * y.size)
        top = min(float(np.max(y[:s])), float(np.max(y[s:])))
        bot = max(float(np.min(y[:s])), float(np.min(y[s:])))
        f_hi = 0.6 + 0.3 * u
        f_lo = 0.6 + 0.3 * rng.uniform()
        return {"sat_lo": f_lo * bot, "sat_hi": f_hi * top}
    return {}
