# SPDX-License-Identifier: MIT
"""Synthetic bump tests with a hidden effect, for tests and examples.

The plant is the library itself (paper parameters unless overridden), with
at most one effect switched on, simulated at `oversample` times the output
rate with the library's default (high) Oustaloup order, then sampled at the
output rate; white Gaussian sensor noise is added to p_c. Effect sizes are
given in the units the diagnosis reports:

    dead_time  s                      lag        s
    backlash   dead-band full width, input units (the library gets x units)
    nozzle     x_1/2, input units; nozzle_bias (gap above the inflection,
               units of x_1/2; 0 = at the inflection)
    saturation sat_lo, sat_hi, output units
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import excite, holdout, lib, model, sensor


def bump_input(n: int, fs: float, rng: np.random.Generator, amp: float = 1.0,
               hold=(0.06, 0.4), rest: float = 0.1, min_step: float = 0.15) -> np.ndarray:
    """Random steps (excite.steps)."""
    return excite.steps(n, fs, rng, amp, hold, rest, min_step)


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
    effects: dict = field(default_factory=dict)     # {name: params} hidden

    @property
    def noise_floor(self) -> float:
        """floor_on the tail split (holdout.layout's default)."""
        return self.floor_on(holdout.layout(self.e.size))

    def floor_on(self, split) -> float:
        """NRMSE on split's held-out part of a perfect model whose output
        offset is fitted on its fit part: what every disturbance the sensor
        added (noise, drift, quantisation) leaves. Judge a diagnosis against
        the floor of the split it validated on (Diagnosis.split): the
        default split can hold out blocks instead of the tail."""
        dist = self.pc - self.clean
        fit_d = np.concatenate([dist[s] for s in split.fit_slices()])
        r = np.concatenate([dist[s] for s in split.held_slices()]) - float(np.mean(fit_d))
        held_pc = np.concatenate([self.pc[s] for s in split.held_slices()])
        return float(np.sqrt(np.mean(r * r))) / float(np.std(held_pc))

    def comments(self) -> list[str]:
        fx = ", ".join(f"{k}={v:.6g}" for k, v in self.effect_params.items()) or "-"
        return [f"pneufrac-fit generate: config={self.config} effect={self.effect} ({fx})",
                f"fs={self.fs:g} Hz, noise sd={self.noise_sd:.6g} (output units)"]


def generate(config: str = "dd", effect: str = "none", effect_params: dict | None = None,
             *, n: int = 6000, fs: float = 1000.0, noise: float = 0.005,
             oversample: int = 4, seed: int = 0, amp: float = 1.0,
             params: dict | None = None, e: np.ndarray | None = None,
             effects: dict | None = None, order: int = 0, wh: float = 0.0,
             noise_kind: str = "white", drift: float = 0.0, adc_bits: int = 0,
             input_kind: str = "steps", rest: float = 0.1) -> Dataset:
    """One record. noise is the sensor noise sd as a fraction of the clean
    output's span (max - min); drift a slow wander of that peak-to-peak
    fraction; adc_bits quantises e and pc over 110 % of their ranges.
    effects ({name: params}) hides several effects at once (effect and
    effect_params: one). order and wh (rad/s) choose the plant's Oustaloup
    approximation (0: the library's defaults)."""
    rng = np.random.default_rng(seed)
    p = lib.default_params(config)
    p.update(params or {})
    fxs = dict(effects or {})
    if effect != "none":
        fxs[effect] = dict(effect_params or {})
    if e is None:
        e = excite.make(input_kind, n, fs, rng, amp, rest)
    fx = {}
    for name, ev in fxs.items():
        fx.update(plant_effects(name, ev, p))
    ctl = lib.Controller(config, p, fx, fs * oversample, order=order, wh=wh)
    clean = ctl.run(np.repeat(e, oversample))[::oversample]
    span = float(np.ptp(clean))
    sd = noise * span
    pc = clean + sensor.coloured(clean.size, sd, noise_kind, rng)
    if drift > 0:
        pc = pc + sensor.drift(clean.size, fs, drift * span, rng)
    em = e
    if adc_bits:
        pad_y, pad_e = 0.05 * span, 0.05 * float(np.ptp(e))
        pc = sensor.adc(pc, adc_bits, float(np.min(clean)) - pad_y, float(np.max(clean)) + pad_y)
        em = sensor.adc(e, adc_bits, float(np.min(e)) - pad_e, float(np.max(e)) + pad_e)
    t = np.arange(e.size) / fs
    name = "+".join(fxs) if fxs else "none"
    ev = dict(effect_params or {}) if len(fxs) <= 1 else {k: v for d in fxs.values() for k, v in d.items()}
    if len(fxs) == 1:
        ev = next(iter(fxs.values()))
    return Dataset(t, em, pc, clean, fs, config, name, ev, sd, p, fxs)


def plant_effects(effect: str, ev: dict, p: dict) -> dict:
    """Effect sizes in report units to the library's pf_effects for the
    plant p (backlash and nozzle act on x = ce e - cy y: input units times
    this plant's ce = b/(a+b))."""
    ce = p["b"] / (p["a"] + p["b"])
    if effect == "dead_time":
        return {"dead_time": ev["dead_time"]}
    if effect == "lag":
        return {"lag": ev["lag"]}
    if effect == "saturation":
        return {"saturate": model.sat_kind(ev), "sat_lo": ev["sat_lo"], "sat_hi": ev["sat_hi"]}
    if effect == "backlash":
        return {"backlash": ev["deadband"] * ce}
    if effect == "nozzle":
        return {"nozzle_xh": ev["nozzle_xh"] * ce, "nozzle_bias": ev.get("nozzle_bias", 0.0)}
    return {}


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
        # 5..25 % compression at the inflection; biased at the equilibrium
        # anywhere from before the inflection to well beyond it
        return {"nozzle_xh": (1.5 + 2.5 * u) * amp,
                "nozzle_bias": float(rng.uniform(-0.3, 1.0))}
    if effect == "saturation":
        # Limits inside the range that both the fit part and the held-out
        # part (holdout.layout) reach, so that both see the clipping.
        y = linear_output(config, e, fs, params=params)
        split = holdout.layout(y.size)
        parts = [np.concatenate([y[s] for s in split.fit_slices()]),
                 np.concatenate([y[s] for s in split.held_slices()])]
        top = min(float(np.max(p)) for p in parts)
        bot = max(float(np.min(p)) for p in parts)
        f_hi = 0.6 + 0.3 * u
        f_lo = 0.6 + 0.3 * rng.uniform()
        return {"sat_lo": f_lo * bot, "sat_hi": f_hi * top}
    return {}
