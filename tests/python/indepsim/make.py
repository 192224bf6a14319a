# SPDX-License-Identifier: MIT
"""One record from a recipe and a seed: draw the plant, the input and the
effect sizes, simulate at OVERSAMPLE times the data rate, acquire, add
noise and quantise, and describe all of it in a truth dict."""
from __future__ import annotations

import math
import zlib
from dataclasses import dataclass

import numpy as np

from . import controller, daq, excitation, noise, plant, simulate
from .diffusive import NODES_PER_DECADE
from .effects import Effects, U0_INFLECTION, nozzle_F
from .scenarios import CATALOGUE, SEED_MAX, Recipe, config_for

OVERSAMPLE = 8
VAL_FRACTION = 0.3   # pneufrac-fit's default held-out part: the last 30 % (docs/analysis.md)


@dataclass
class Record:
    t: np.ndarray
    e: np.ndarray
    pc: np.ndarray
    truth: dict
    noise: np.ndarray   # what the DAQ added to pc: measured minus noise-free sampled output


def floor_over(pc: np.ndarray, noise: np.ndarray, held) -> float:
    """The true noise floor of a held-out NRMSE: the noise's rms over the
    std of the measured output, both over the held-out samples taken
    together (pneufrac-fit's `record.held_out` [start, stop) pairs), as the
    tool computes its own NRMSE. Needed because the held-out part is not
    always the last 30 % (`--holdout blocks`)."""
    idx = np.concatenate([np.arange(a, b) for a, b in held]) if len(held) else np.arange(0)
    if idx.size < 2 or idx.min() < 0 or idx.max() >= min(pc.size, noise.size):
        raise ValueError("held-out samples outside the record")
    sd = float(np.std(pc[idx]))
    if not sd > 0:
        raise ValueError("the output does not move over the held-out samples")
    return float(np.sqrt(np.mean(noise[idx] ** 2)) / sd)


def load_noise(path) -> np.ndarray | None:
    """The noise file a simulator wrote beside its record (STEM.noise.csv),
    or None when it is missing or unreadable (records made before it was
    written)."""
    try:
        return np.loadtxt(path, ndmin=1)
    except (OSError, ValueError):
        return None


def true_floor_held(pc: np.ndarray, noise: np.ndarray | None, held, n_tool, fallback: float) -> float:
    """floor_over the tool's held-out samples; `fallback` (the simulator's
    floor over the last 30 %) when the tool's record does not line up with
    this one sample for sample (a resampled or trimmed record) or its
    held-out part is unknown. Shared by both simulators' benchmarks."""
    if noise is not None and held and n_tool == pc.size:
        try:
            return floor_over(pc, noise, held)
        except ValueError:
            pass
    return fallback


def _rng(name: str, seed: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence([seed, zlib.crc32(name.encode())]))


def _u(rng, lo_hi) -> float:
    lo, hi = lo_hi
    return float(rng.uniform(lo, hi)) if hi > lo else float(lo)


def _effects(req: dict, rng, fs: float, e_dev: np.ndarray, pc_dev: np.ndarray,
             pc0: float) -> Effects:
    fx = Effects()
    if "dead_time" in req:
        fx.dead_time = _u(rng, req["dead_time"]["samples"]) / fs
    if "lag" in req:
        fx.lag = _u(rng, req["lag"]["samples"]) / fs
    if "saturation" in req:
        # Only a side the output visits (a quarter of its range or more) can clip.
        up, down = max(float(pc_dev.max()), 0.0), max(-float(pc_dev.min()), 0.0)
        sides = [s for s, ok in (("hi", up >= 0.25 * (up + down)),
                                 ("lo", down >= 0.25 * (up + down))) if ok]
        side = str(rng.choice(sides + (["both"] if len(sides) == 2 else [])))
        f = req["saturation"]["frac"]
        if side in ("hi", "both"):
            fx.sat_hi = pc0 + _u(rng, f) * float(pc_dev.max())
        if side in ("lo", "both"):
            fx.sat_lo = pc0 + _u(rng, f) * float(pc_dev.min())
        fx.sat_wind = req["saturation"].get("stop") == "wind"
    if "backlash" in req:
        fx.deadband = _u(rng, req["backlash"]["span_frac"]) * float(np.ptp(e_dev))
        fx.backlash_side = float(rng.choice([-1.0, 1.0]))  # at rest after a move
    if "nozzle" in req:
        n = req["nozzle"]
        fx.nozzle_xh = _u(rng, n["amp_multiple"]) * float(np.max(np.abs(e_dev)))
        if n["u0"] == "off":
            fx.nozzle_u0 = _u(rng, (0.25, 0.4)) if rng.uniform() < 0.5 else _u(rng, (0.85, 1.3))
        else:
            fx.nozzle_u0 = U0_INFLECTION
    return fx


def _truth_effects(fx: Effects, fs: float) -> list[dict]:
    out = []
    if fx.dead_time > 0:
        out.append({"cause": "dead_time", "params": {"dead_time": fx.dead_time,
                                                     "dead_time_samples": fx.dead_time * fs}})
    if fx.lag > 0:
        out.append({"cause": "lag", "params": {"lag": fx.lag}})
    if fx.saturates():
        out.append({"cause": "saturation", "params": {
            "sat_lo": fx.sat_lo if math.isfinite(fx.sat_lo) else None,
            "sat_hi": fx.sat_hi if math.isfinite(fx.sat_hi) else None,
            "relay_memory": "winds on" if fx.sat_wind else "runs on"}})
    if fx.deadband > 0:
        out.append({"cause": "backlash", "params": {"deadband": fx.deadband,
                                                    "start_side": fx.backlash_side}})
    if fx.nozzle_xh > 0:
        out.append({"cause": "nozzle", "params": {
            "nozzle_xh": fx.nozzle_xh, "nozzle_u0": fx.nozzle_u0,
            "bias_pb_over_ps": float(nozzle_F(fx.nozzle_u0)),
            "at_inflection": bool(abs(fx.nozzle_u0 - U0_INFLECTION) < 1e-12)}})
    return out


def make(name: str, seed: int) -> Record:
    if name not in CATALOGUE:
        raise KeyError(name)
    if not 0 <= seed <= SEED_MAX:
        raise ValueError(f"seed must lie in [0, {SEED_MAX}]")
    rc: Recipe = CATALOGUE[name]
    rng = _rng(name, seed)
    config = config_for(rc, seed)
    params = plant.draw(config, rc.get("spread"), rng)
    fs = rc.get("fs")
    duration = float(rng.choice(rc.get("durations")))
    kind = str(rng.choice(rc.get("excitations")))
    amp = float(10.0 ** rng.uniform(-0.5, 0.5))
    exc = excitation.draw(kind, rng, amp, duration)
    if rc.get("op") == "zero":
        e0, pc0 = 0.0, 0.0
    else:
        e0, pc0 = float(rng.uniform(-2.0, 2.0)), float(rng.uniform(3.0, 12.0))
    n = int(round(duration * fs))
    fs_int = OVERSAMPLE * fs
    pre = excitation.pre_roll(exc)
    t_start = -pre - 2.0 / fs
    n_int = int(math.ceil((duration + 2.0 / fs - t_start) * fs_int)) + 1
    t_int = t_start + np.arange(n_int) / fs_int
    e_int = excitation.evaluate(exc, t_int)
    span_t = duration + pre
    lin = simulate.run(config, params, Effects(), e_int, fs_int, duration=span_t)
    rec = t_int >= 0.0
    fx = _effects(rc.effects, rng, fs, e_int[rec], lin.line[rec], pc0)
    run = simulate.run(config, params, fx, e_int, fs_int, pc0=pc0, duration=span_t) \
        if fx.names() else lin

    jitter = float(rng.choice(rc.get("jitter")))
    t_true = daq.sample_times(n, fs, rng, jitter)
    e_clean = e0 + daq.average(e_int, t_start, fs_int, t_true, fs)
    pc_clean = pc0 + daq.average(run.line, t_start, fs_int, t_true, fs)

    model = str(rng.choice(rc.get("noises")))
    phi = _u(rng, (0.5, 0.95)) if model == "ar1" else 0.0
    pc_span = float(np.ptp(pc_clean))
    sd = _u(rng, rc.get("noise_frac")) * pc_span
    pc = pc_clean + sd * noise.draw(model, n, rng, phi)
    drift_info = None
    dfrac = rc.get("drift_frac")
    if dfrac:
        d, drift_info = noise.drift(t_true, _u(rng, dfrac) * pc_span, rng)
        pc = pc + d
    e_sd = rc.get("e_noise_frac") * float(np.ptp(e_clean))
    e = e_clean + (e_sd * noise.white(n, rng) if e_sd > 0 else 0.0)
    adc = None
    if rc.get("adc"):
        use_e, use_pc = _u(rng, (0.3, 0.9)), _u(rng, (0.3, 0.9))
        e_lo, e_hi = daq.adc_range(e, use_e)
        p_lo, p_hi = daq.adc_range(pc, use_pc)
        e, pc = daq.quantise(e, e_lo, e_hi), daq.quantise(pc, p_lo, p_hi)
        adc = {"bits": daq.BITS, "e_range": [e_lo, e_hi], "pc_range": [p_lo, p_hi],
               "e_lsb": (e_hi - e_lo) / (2 ** daq.BITS - 1),
               "pc_lsb": (p_hi - p_lo) / (2 ** daq.BITS - 1)}
    t = daq.stamps(t_true)

    # How far the effects move the sampled output, against the noise: an
    # upper bound on what a fit of the linear model can be shown to miss.
    eff_rms = 0.0
    if fx.names():
        lin_s = pc0 + daq.average(lin.line, t_start, fs_int, t_true, fs)
        eff_rms = float(np.sqrt(np.mean((pc_clean - lin_s) ** 2)))
    resid = pc - pc_clean
    nv = int(round(n * VAL_FRACTION))
    val = slice(n - nv, n)
    truth = {
        "scenario": name, "seed": seed, "class": rc.get("cls"), "expected": rc.get("expected"),
        "description": rc.description, "config": config,
        "params": params, "groups": controller.groups(config, params),
        "causes": fx.names(), "effects": _truth_effects(fx, fs),
        "operating_point": {"e0": e0, "pc0": pc0},
        "excitation": exc,
        "record": {"fs": fs, "n": n, "duration": duration, "internal_rate": fs_int,
                   "pre_roll": pre, "jitter_sd_periods": jitter,
                   "stamp_resolution": daq.STAMP_RESOLUTION,
                   "daq": "boxcar mean over each sample period, same on e and pc"},
        "noise": {"model": model, "sd": sd, "sd_frac_of_span": sd / pc_span if pc_span else 0.0,
                  "ar1_phi": phi if model == "ar1" else None, "e_sd": e_sd,
                  "adc": adc, "drift": drift_info,
                  "realised_sd": float(np.std(resid)),
                  "realised_sd_val": float(np.std(resid[val])),
                  "effect_rms": eff_rms, "effect_rms_over_sd": eff_rms / sd if sd else None,
                  "noise_floor_val": floor_over(pc, resid, [(val.start, val.stop)])},
        "simulator": {"approximation": "diffusive quadrature of s^-alpha",
                      "nodes_per_decade": NODES_PER_DECADE,
                      "band": list(controller.band_for(fs_int, span_t)),
                      "discretisation": "closed loop, exact for inputs linear between "
                                        "internal samples (FOH)",
                      "oversample": OVERSAMPLE},
    }
    return Record(t, e, pc, truth, resid)


def write(rec: Record, out_dir, stem: str) -> tuple[str, str]:
    """DIR/STEM.csv (t,e,pc), DIR/STEM.truth.json, and DIR/STEM.noise.csv
    (the noise added to pc, one value per line, for floor_over)."""
    import json
    from pathlib import Path
    d = Path(out_dir)
    csv = d / f"{stem}.csv"
    js = d / f"{stem}.truth.json"
    with open(csv, "w") as f:
        f.write("t,e,pc\n")
        for row in zip(rec.t, rec.e, rec.pc):
            f.write("%.6f,%.10g,%.10g\n" % row)
    with open(js, "w") as f:
        json.dump(rec.truth, f, indent=1, sort_keys=False)
        f.write("\n")
    np.savetxt(d / f"{stem}.noise.csv", rec.noise, fmt="%.10g")
    return str(csv), str(js)
