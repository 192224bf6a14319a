# SPDX-License-Identifier: MIT
"""Hidden-effect cases shared by the tests and the detection-limit script."""
from __future__ import annotations

import math

import numpy as np

from pneufrac_fit import data, diagnose, generate

FS = 1000.0
HOLD = tuple(float(x) for x in __import__("os").environ.get("PF_HOLD", "0.06,0.4").split(","))
N = 5000          # 5 s bump test at 1 kHz
NOISE = float(__import__("os").environ.get("PF_TEST_NOISE", "0.005"))


def make(config: str, effect: str, seed: int, n: int = N, size: float | None = None,
         noise: float = NOISE, scale: float = 1.0):
    """A record with one hidden effect drawn at random (seeded). scale
    shrinks the effect toward 'off' for the detection-limit test."""
    rng = np.random.default_rng(seed)
    params = generate.perturbed_params(config, rng)
    e = generate.bump_input(n, FS, rng, hold=HOLD)
    ep = generate.draw_effect(effect, config, rng, FS, e, size, params)
    ep = shrink(effect, ep, scale, config, e, params)
    ds = generate.generate(config, effect, ep, n=n, fs=FS, noise=noise, seed=seed + 7, e=e,
                           params=params)
    return ds


def shrink(effect, ep, scale, config, e, params=None):
    if scale == 1.0:
        return ep
    out = dict(ep)
    if effect in ("dead_time", "lag", "backlash"):
        k = next(iter(ep))
        out[k] = ep[k] * scale
    elif effect == "nozzle":
        out["nozzle_xh"] = ep["nozzle_xh"] / scale
    elif effect == "saturation":
        y = generate.linear_output(config, e, FS, params=params)
        out["sat_hi"] = float(np.max(y)) + (ep["sat_hi"] - float(np.max(y))) * scale
        out["sat_lo"] = float(np.min(y)) + (ep["sat_lo"] - float(np.min(y))) * scale
    return out


def run(ds, jobs: int = 1):
    rec = data.make_record(ds.t, ds.e, ds.pc, "synthetic")
    return diagnose.diagnose(rec, ds.config, jobs=jobs, progress=False,
                             oversample=int(__import__("os").environ.get("PF_OS", "2")))


def check(ds, d) -> list[str]:
    """Failures against the issue's acceptance rules (empty: pass)."""
    bad = []
    truth = ds.effect
    if d.cause != truth:
        bad.append(f"cause {d.cause}, expected {truth}")
        return bad
    p, t = d.extended.effect_params, ds.effect_params
    if truth == "dead_time":
        if abs(p["dead_time_samples"] - t["dead_time"] * ds.fs) > 2:
            bad.append(f"dead time {p['dead_time_samples']} samples, true {t['dead_time'] * ds.fs:.2f}")
    elif truth in ("lag", "backlash", "nozzle"):
        key = {"lag": "lag", "backlash": "deadband", "nozzle": "nozzle_xh"}[truth]
        if not abs(p[key] / t[key] - 1) <= 0.25:
            bad.append(f"{key} {p[key]:.4g}, true {t[key]:.4g}")
    elif truth == "saturation":
        span = float(np.ptp(generate.linear_output(ds.config, ds.e, ds.fs, params=ds.params)))
        for k in ("sat_lo", "sat_hi"):
            if not abs(p[k] - t[k]) <= 0.05 * span:
                bad.append(f"{k} {p[k]:.4g}, true {t[k]:.4g} (span {span:.4g})")
    if truth != "none":
        before, after = d.baseline.nrmse_val, d.extended.nrmse_val
        floor = ds.noise_floor
        if not after <= 0.5 * (before + floor):
            bad.append(f"validation NRMSE {before:.4f} -> {after:.4f}, floor {floor:.4f}: "
                       "not halfway to the floor")
    return bad
