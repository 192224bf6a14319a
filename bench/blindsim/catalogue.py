# SPDX-License-Identifier: MIT
"""The records: which controller, input, noise and effects, and their truth.

A record is named by its scenario and a seed; everything random (the
perturbed parameters, the input, the effect sizes, the noise) is drawn
from numpy's generator seeded by (seed, crc32(name)), so the command in
each truth file remakes the record exactly.

Effect sizes are drawn per class: `obvious` well above the noise, and
`marginal` near what a record can show (a dead time or lag of about one
data sample, a dead band under 1 % of the input span, clipping of the last
few percent, a nozzle visited over +-6-10 % of its gap scale).
"""
from __future__ import annotations

import math
import zlib

import numpy as np

from . import excitation, sensors
from .nozzle import NozzleCurve
from .plant import Controller, Effects, simulate

EFFECTS = ("dead_time", "lag", "backlash", "saturation", "nozzle")

# The paper's Examples 4 (p), 6 (dd), 7 (id) and Remark 3 (pid, as
# docs/pid.md). The perturbation below keeps none of them exact.
PAPER = {
    "p": dict(b=9, a=1, k1=0.1, k2=0.1, A=2, ks=20, tau=1e-3, pmin=1, pmax=10, beta=0.8, q=0.9),
    "dd": dict(b=9, a=1, k1=0.1, k2=0.1, A=2, ks=20, tau=1e-3, pmin=1, pmax=10, beta=0.8, q=0.9,
               nu=0.94, RC=0.1),
    "id": dict(b=9, a=1, k1=2, k2=5, A=2, ks=20, tau=1e-3, pmin=1, pmax=10, beta=0.8, q=0.0,
               w=0.94, RC=0.1),
    "pid": dict(b=9, a=1, k1=2, k2=5, A=2, ks=20, tau=1e-3, pmin=1, pmax=10, beta=0.8, q=0.0,
                nu=0.94, w=0.94, RCd=0.01, RCi=0.1),
}


def _s(config, exc, noise="white", fs=1000, dur=20.0, rest=True, adc=0, jitter=0.0,
       effects=(), cls=None, size="obvious", columns=None):
    return dict(config=config, exc=exc, noise=noise, fs=fs, dur=dur, rest=rest, adc=adc,
                jitter=jitter, effects=tuple(effects), size=size, columns=columns,
                cls=cls or ("clean" if not effects else ("marginal" if size == "marginal"
                                                         else ("two" if len(effects) > 1 else "one"))))


SCENARIOS = {
    # clean records: every one must give `none`
    "clean-p-steps": _s("p", "steps"),
    "clean-dd-prbs-ar2": _s("dd", "prbs", "ar2"),
    "clean-id-ramps-adc12": _s("id", "ramps", adc=12),
    "clean-pid-multisine-pink": _s("pid", "multisine", "pink", rest=False),
    "clean-p-wander-ar2-adc12": _s("p", "wander", "ar2", rest=False, adc=12),
    "clean-dd-setpoints-drift": _s("dd", "setpoints", "drift"),
    "clean-id-steps-pink-adc10": _s("id", "steps", "pink", adc=10),
    "clean-pid-steps-jitter": _s("pid", "steps", jitter=0.2),
    "clean-p-5s-prbs": _s("p", "prbs", dur=5.0),
    "clean-id-5s-multisine-ar2": _s("id", "multisine", "ar2", dur=5.0, rest=False),
    "clean-dd-10k-steps": _s("dd", "steps", fs=10000, dur=5.0),
    "clean-pid-10k-wander-pink": _s("pid", "wander", "pink", fs=10000, dur=5.0, rest=False),
    "clean-id-ramps-drift": _s("id", "ramps", "drift", rest=False),
    "clean-dd-columns-jitter": _s("dd", "setpoints", jitter=0.15,
                                  columns=("time", "error", "output")),
    # one effect, sized well above the noise
    "dead_time-dd-steps": _s("dd", "steps", effects=["dead_time"]),
    "dead_time-pid-prbs-ar2": _s("pid", "prbs", "ar2", effects=["dead_time"]),
    "dead_time-p-10k-steps": _s("p", "steps", fs=10000, dur=5.0, effects=["dead_time"]),
    "lag-p-steps": _s("p", "steps", effects=["lag"]),
    "lag-id-ramps-pink": _s("id", "ramps", "pink", effects=["lag"]),
    "lag-pid-setpoints-drift": _s("pid", "setpoints", "drift", effects=["lag"]),
    "lag-dd-5s-steps": _s("dd", "steps", dur=5.0, effects=["lag"]),
    "backlash-dd-steps": _s("dd", "steps", effects=["backlash"]),
    "backlash-id-ramps-ar2-adc12": _s("id", "ramps", "ar2", adc=12, effects=["backlash"]),
    "backlash-pid-wander": _s("pid", "wander", rest=False, effects=["backlash"]),
    "saturation-p-steps": _s("p", "steps", effects=["saturation"]),
    "saturation-id-multisine-pink": _s("id", "multisine", "pink", rest=False, effects=["saturation"]),
    "saturation-pid-steps": _s("pid", "steps", effects=["saturation"]),
    "nozzle-dd-steps": _s("dd", "steps", effects=["nozzle"]),
    "nozzle-id-ramps": _s("id", "ramps", effects=["nozzle"]),
    "nozzle-p-setpoints-ar2": _s("p", "setpoints", "ar2", effects=["nozzle"]),
    "nozzle-pid-steps-jitter": _s("pid", "steps", jitter=0.2, effects=["nozzle"]),
    # two effects at once
    "two-lag-backlash-dd": _s("dd", "steps", effects=["lag", "backlash"]),
    "two-dead_time-saturation-p": _s("p", "steps", effects=["dead_time", "saturation"]),
    "two-nozzle-lag-id": _s("id", "ramps", effects=["nozzle", "lag"]),
    "two-backlash-saturation-pid": _s("pid", "steps", "ar2", effects=["backlash", "saturation"]),
    "two-dead_time-backlash-id": _s("id", "setpoints", effects=["dead_time", "backlash"]),
    "two-lag-saturation-dd": _s("dd", "prbs", "pink", effects=["lag", "saturation"]),
    "two-nozzle-dead_time-p": _s("p", "steps", effects=["nozzle", "dead_time"]),
    "two-backlash-lag-pid-5s": _s("pid", "steps", dur=5.0, effects=["backlash", "lag"]),
    # at the detection limit: missing it is no fault, naming another cause is
    "marginal-dead_time-p": _s("p", "steps", effects=["dead_time"], size="marginal"),
    "marginal-lag-dd": _s("dd", "steps", effects=["lag"], size="marginal"),
    "marginal-backlash-id": _s("id", "steps", effects=["backlash"], size="marginal"),
    "marginal-saturation-pid": _s("pid", "steps", effects=["saturation"], size="marginal"),
    "marginal-nozzle-dd": _s("dd", "ramps", effects=["nozzle"], size="marginal"),
}


def perturbed(config: str, rng: np.random.Generator) -> dict:
    p = dict(PAPER[config])

    def scale(v, f):
        return v * math.exp(rng.uniform(-f, f))

    ratio = scale(p["b"] / p["a"], 0.15)
    p["a"], p["b"] = 1.0, ratio
    for k in ("k1", "k2"):
        p[k] = scale(p[k], 0.2)
    p["ks"] = scale(p["ks"], 0.2)
    p["tau"] = scale(p["tau"], 0.35)
    p["pmax"] = scale(p["pmax"], 0.25)
    p["beta"] = min(1.0, p["beta"] + rng.uniform(-0.06, 0.06))
    if p["q"] > 0:
        p["q"] = min(1.0, p["q"] + rng.uniform(-0.04, 0.04))
    for k in ("RC", "RCd", "RCi"):
        if k in p:
            p[k] = scale(p[k], 0.35)
    if "w" in p:
        p["w"] = min(1.0, p["w"] + rng.uniform(-0.04, 0.04))
    if "nu" in p:  # pneufrac's pid needs nu <= w; keep the truth representable
        p["nu"] = min(p.get("w", 1.0), p["nu"] + rng.uniform(-0.04, 0.04))
    return p


def groups(config: str, p: dict) -> dict:
    """The truth in pneufrac's groups (docs/analysis.md, section 1)."""
    ce, cy = p["b"] / (p["a"] + p["b"]), p["a"] / (p["a"] + p["b"])
    g = dict(K=ce * p["k1"] * p["k2"] / p["pmin"],
             L=cy * p["k1"] * p["k2"] * (p["A"] / p["ks"]) / p["pmin"],
             rho=p["pmax"] / p["pmin"], tau=p["tau"], beta=p["beta"], q=p["q"])
    for k in ("RC", "nu", "w", "RCd"):
        if k in p:
            g[k] = p[k]
    if "RCi" in p:
        g["RCi/RCd"] = p["RCi"] / p["RCd"]
    return g


def build(name: str, seed: int, noise: str | None = None) -> tuple[dict, dict]:
    """Return (columns {t, e, pc}, truth) for scenario `name`, seed `seed`;
    `noise` replaces the scenario's noise kind (every other draw unchanged)."""
    if name not in SCENARIOS:
        raise KeyError(f"unknown scenario {name}")
    if noise is not None and noise not in sensors.NOISE_KINDS:
        raise ValueError(f"unknown noise {noise}")
    sp = dict(SCENARIOS[name], **({"noise": noise} if noise else {}))
    rng = np.random.default_rng([seed, zlib.crc32(name.encode())])
    cfg, fs, dur = sp["config"], float(sp["fs"]), float(sp["dur"])
    p = perturbed(cfg, rng)
    ce = p["b"] / (p["a"] + p["b"])
    over = 20 if fs <= 2000 else 5
    h = 1.0 / (fs * over)
    runin = 0.0 if sp["rest"] else 2.0
    rest = rng.uniform(0.3, 0.8) if sp["rest"] else 0.0
    amp = rng.uniform(0.7, 1.5)
    e_fn = excitation.make(sp["exc"], rng, -runin, dur + 0.01, amp, rest=rest)
    n_int = int(round((dur + runin + 2.0 / fs) / h)) + 1
    t_int = -runin + np.arange(n_int) * h
    e_int = e_fn(t_int)
    ctrl = Controller(cfg, p)
    clean = simulate(ctrl, Effects(), e_int, h)

    fx = Effects()
    truth_fx = {}
    marg = sp["size"] == "marginal"
    e_span = float(np.ptp(e_int[t_int >= 0]))
    for eff in sp["effects"]:
        if eff == "dead_time":
            samples = rng.uniform(0.9, 1.4) if marg else rng.uniform(3.0, 12.0)
            fx.line_delay = samples / fs
            truth_fx["dead_time"] = {"dead_time": fx.line_delay, "dead_time_samples": samples}
        elif eff == "lag":
            fx.line_lag = rng.uniform(0.8, 1.3) / fs if marg else rng.uniform(4e-3, 25e-3)
            if fs > 2000 and not marg:
                fx.line_lag = rng.uniform(1e-3, 6e-3)
            truth_fx["lag"] = {"lag": fx.line_lag}
        elif eff == "backlash":
            width_e = e_span * (rng.uniform(0.004, 0.008) if marg else rng.uniform(0.02, 0.05))
            fx.play_x = width_e * ce
            fx.play_start = rng.choice([-1.0, 1.0])
            truth_fx["backlash"] = {"deadband": width_e}
        elif eff == "saturation":
            z = clean["pc"][t_int >= 0] / p["k2"]
            lo, hi = z.min(), z.max()
            frac = (lambda: rng.uniform(0.93, 0.97)) if marg else (lambda: rng.uniform(0.6, 0.85))
            side = rng.integers(0, 3)  # 0 both, 1 supply only, 2 exhaust only
            if side in (0, 1) and hi > 0:
                fx.z_hi = hi * frac()
            if side in (0, 2) and lo < 0:
                fx.z_lo = lo * frac()
            truth_fx["saturation"] = {"sat_lo": fx.z_lo * p["k2"], "sat_hi": fx.z_hi * p["k2"]}
        elif eff == "nozzle":
            x = clean["x"][t_int >= 0]
            x_amp = max(abs(x.min()), abs(x.max()))
            # the equilibrium gap: well closed (gain rising as it opens) or
            # well open (gain falling); in pneufrac's terms a bias about -0.35
            # or 0.5-1.3, never the inflection
            gap = rng.uniform(0.3, 0.5) if rng.random() < 0.5 else rng.uniform(1.6, 2.4)
            reach = rng.uniform(0.06, 0.1) if marg else rng.uniform(0.3, 0.6)
            reach = min(reach, 0.8 * gap)  # the flapper never seats on the nozzle
            fx.nozzle_g1 = x_amp / reach
            fx.nozzle_gap0 = gap * fx.nozzle_g1
            truth_fx["nozzle"] = {}
    full = simulate(ctrl, fx, e_int, h) if sp["effects"] else clean

    n = int(round(dur * fs))
    tk = sensors.instants(n, fs, sp["jitter"], rng)
    e_true = e_fn(tk)
    pc_true = np.interp(tk, t_int, full["line"])
    pc_lin = np.interp(tk, t_int, clean["line"])
    span = float(np.ptp(pc_true))
    noise_frac = rng.uniform(0.003, 0.008)
    sd_pc = noise_frac * span
    sd_e = 0.001 * e_span
    e0 = rng.uniform(-2.0, 2.0)
    pc0 = span * rng.uniform(2.0, 6.0)
    pc_meas = pc0 + pc_true + sd_pc * sensors.noise(sp["noise"], n, rng)
    e_meas = e0 + e_true + sd_e * rng.standard_normal(n)
    if sp["adc"]:
        pc_meas = sensors.adc(pc_meas, pc0 + pc_true.min() - 1.5 * span,
                              pc0 + pc_true.max() + 1.5 * span, sp["adc"])
        e_meas = sensors.adc(e_meas, e0 - 2.5 * amp, e0 + 2.5 * amp, sp["adc"])
    if "saturation" in truth_fx:
        s = truth_fx["saturation"]
        s["sat_lo"] = pc0 + s["sat_lo"] if math.isfinite(s["sat_lo"]) else None
        s["sat_hi"] = pc0 + s["sat_hi"] if math.isfinite(s["sat_hi"]) else None
    if "nozzle" in truth_fx:
        x = full["x"][t_int >= 0]
        xh, bias, misfit = NozzleCurve(fx.nozzle_g1, fx.nozzle_gap0).equivalent(x.min(), x.max())
        truth_fx["nozzle"] = {"nozzle_xh": xh / ce, "nozzle_bias": bias,
                              "gap0_over_g1": fx.nozzle_gap0 / fx.nozzle_g1,
                              "equivalent_misfit_over_span": misfit / max(1e-300, np.ptp(x))}
    val = slice(int(0.7 * n), n)
    floor = float(np.sqrt(np.mean((pc_meas - pc0 - pc_true)[val] ** 2)) / np.std(pc_meas[val]))
    truth = {
        "name": name, "seed": seed, "class": sp["cls"], "size": sp["size"], "config": cfg,
        "fs": fs, "n": n, "duration": dur, "internal_rate": fs * over,
        "excitation": sp["exc"], "rest": rest, "run_in": runin, "noise": sp["noise"],
        "noise_sd": sd_pc, "noise_over_span": noise_frac, "adc_bits": sp["adc"],
        "jitter_periods": sp["jitter"], "columns": list(sp["columns"] or ("t", "e", "pc")),
        "params": p, "groups": groups(cfg, p), "e0": e0, "pc0": pc0,
        "causes": sorted(truth_fx), "effects": truth_fx,
        "effect_rms_over_noise": float(np.sqrt(np.mean((pc_true - pc_lin) ** 2)) / sd_pc),
        "floor_val": floor,
        "remake": (f"PYTHONPATH=bench .venv/bin/python -m blindsim make {name} --seed {seed}"
                   + (f" --noise {noise}" if noise else "") + " --out DIR"),
    }
    # The noise the sensors added (quantisation included), for the floor
    # over whichever samples the tool holds out.
    return {"t": tk, "e": e_meas, "pc": pc_meas, "noise": pc_meas - pc0 - pc_true}, truth
