# SPDX-License-Identifier: MIT
"""Residual evidence: what a fitted model gets wrong, in numbers and words."""
from __future__ import annotations

import math

import numpy as np

from . import model, noise

Z99 = 2.5758293035489  # two-sided 99 % normal quantile
MAXLAG = 40


def xcorr(a: np.ndarray, b: np.ndarray, lags) -> np.ndarray:
    """Normalised cross-correlation r_ab(k) = sum a[n+k] b[n] / (|a||b|)."""
    a = a - a.mean()
    b = b - b.mean()
    den = math.sqrt(float(a @ a) * float(b @ b)) or 1.0
    out = []
    n = a.size
    for k in lags:
        if k >= 0:
            out.append(float(a[k:] @ b[:n - k]) / den)
        else:
            out.append(float(a[:n + k] @ b[-k:]) / den)
    return np.array(out)


def steps(e: np.ndarray, min_rel: float = 0.02):
    """(index, delta) of every input step larger than min_rel of the span."""
    d = np.diff(e)
    span = float(np.ptp(e)) or 1.0
    k = np.flatnonzero(np.abs(d) > min_rel * span) + 1
    return k, d[k - 1]


def analyse(pb, fr, sd: float) -> dict:
    """Residual findings. The cross-correlation with the input's increments
    uses the residual whitened by its own noise model (noise.fit): noise
    that is coloured but independent of the input then stays inside the
    band +-2.576/sqrt(N), whatever its colour."""
    y, e = pb.y, pb.e_abs
    r = y - fr.sim
    n = r.size
    lags = np.arange(0, MAXLAG + 1)
    acf = xcorr(r, r, lags)
    de = np.diff(e, prepend=e[0])
    clag = np.arange(-MAXLAG, MAXLAG + 1)
    nm = noise.fit(pb.fit_pieces(r))
    rw = np.concatenate([np.zeros(nm.order), nm.whiten(r)])
    ccf = xcorr(rw, de, clag)
    bound = Z99 / math.sqrt(n)

    # residual by input level (signed amplitude), settled part of each hold
    k_st, d_st = steps(e)
    settle = np.ones(n, bool)
    for k in k_st:
        settle[k:k + 10] = False
    lo, hi = float(np.min(e)), float(np.max(e))
    edges = np.linspace(lo, hi, 7)
    amp = []
    for i in range(6):
        m = settle & (e >= edges[i]) & (e <= edges[i + 1] if i == 5 else e < edges[i + 1])
        if m.sum() >= 10:
            amp.append((0.5 * (edges[i] + edges[i + 1]), float(np.mean(r[m])),
                        float(np.std(r[m])), int(m.sum())))

    # residual by step direction: mean over each hold after the step
    seg_end = list(k_st[1:]) + [n]
    rise, fall = [], []
    for k, d, k2 in zip(k_st, d_st, seg_end):
        a, b = k + 5, k2
        if b - a < 5:
            continue
        (rise if d > 0 else fall).append(float(np.mean(r[a:b])))

    # early response after steps: step-aligned, normalised by the step size
    W = 40
    M, S = [], []
    for k, d in zip(k_st, d_st):
        if k < 5 or k + W >= n or (k_st[(k_st > k)][:1] < k + W).any():
            continue
        M.append((y[k - 5:k + W] - y[k - 1]) / d)
        S.append((fr.sim[k - 5:k + W] - fr.sim[k - 1]) / d)
    early = None
    if M:
        Mm, Sm = np.mean(M, 0), np.mean(S, 0)
        best, shifts = None, np.arange(-10.0, 20.25, 0.25)
        j = np.arange(Sm.size, dtype=float)
        errs = []
        for s in shifts:
            shifted = np.interp(j - s, j, Sm)   # model delayed by s samples
            errs.append(float(np.sum((Mm[5:] - shifted[5:]) ** 2)))
        best = float(shifts[int(np.argmin(errs))])
        early = {"measured": Mm, "model": Sm, "lag_samples": best, "offset": 5}

    rs = np.sort(r)
    return {
        "r": r, "acf": acf, "lags": lags, "ccf": ccf, "clags": clag, "noise": nm,
        "bound": bound, "amp": amp, "rise": rise, "fall": fall, "early": early,
        "rms": float(np.sqrt(np.mean(r * r))),
        "acf_out": int(np.sum(np.abs(acf[1:]) > bound)),
        "ccf_out": int(np.sum(np.abs(ccf) > bound)),
        "q99": float(rs[int(0.99 * (n - 1))]), "q01": float(rs[int(0.01 * (n - 1))]),
    }


def _t(x: list) -> tuple[float, float]:
    if len(x) < 2:
        return (x[0] if x else 0.0), math.inf
    return float(np.mean(x)), float(np.std(x, ddof=1) / math.sqrt(len(x)))


def describe(ev: dict, pb, sd: float, floor: float, base) -> list[str]:
    """The baseline's residual evidence, one finding per string."""
    out = []
    fs = pb.setup.fs
    out.append(f"Baseline validation NRMSE {base.nrmse_val:.4f}; noise floor {floor:.4f} "
               f"(sample-to-sample sensor noise sd {sd:.3g}).")
    b = ev["bound"]
    k = int(np.argmax(np.abs(ev["acf"][1:]))) + 1
    out.append(f"Residual autocorrelation: {ev['acf_out']} of {MAXLAG} lags outside the "
               f"white-noise band +-{b:.3f} (largest {ev['acf'][k]:+.2f} at lag {k}); its noise "
               f"model is {ev['noise'].describe()}. Colour alone is no evidence against the "
               "model: noise can be coloured; the test below is.")
    k = int(np.argmax(np.abs(ev["ccf"])))
    lag = int(ev["clags"][k])
    if ev["ccf_out"] > 2 and abs(ev["ccf"][k]) > b:
        out.append(f"Residual (whitened by its noise model) against the input's increments: "
                   f"{ev['ccf_out']} of {2 * MAXLAG + 1} lags outside the 99 % band "
                   f"+-{b:.3f}, largest {ev['ccf'][k]:+.2f} at lag {lag:+d} samples: the "
                   "residual depends on the input, so the model misses structure"
                   + (" right after the input changes." if 0 <= lag <= 15 else "."))
    else:
        out.append("Residual (whitened by its noise model) against the input's increments: "
                   f"inside the 99 % band at {2 * MAXLAG + 1 - ev['ccf_out']} of "
                   f"{2 * MAXLAG + 1} lags: no structure the input explains is left.")
    if ev["early"] is not None:
        ls = ev["early"]["lag_samples"]
        out.append(f"Early response after steps: the measured output follows the model "
                   f"shifted by {ls:+.2f} samples ({ls / fs * 1e3:+.2f} ms).")
    mr, sr = _t(ev["rise"])
    mf, sf = _t(ev["fall"])
    if math.isfinite(sr) and math.isfinite(sf):
        z = (mr - mf) / math.sqrt(sr ** 2 + sf ** 2) if sr + sf > 0 else 0.0
        out.append(f"Step direction: mean residual after rising steps {mr:+.3g}, after falling "
                   f"steps {mf:+.3g} ({z:+.1f} standard errors apart)"
                   + (": hysteresis, the output lags the input's direction (dead band)."
                      if z < -3 else
                      (": direction-dependent error." if abs(z) > 3 else ": no clear direction effect.")))
    if ev["amp"]:
        means = np.array([a[1] for a in ev["amp"]])
        cents = np.array([a[0] for a in ev["amp"]])
        spread = float(np.ptp(means))
        worst = ev["amp"][int(np.argmax(np.abs(means)))]
        if spread > 3 * sd / math.sqrt(max(min(a[3] for a in ev["amp"]), 1)) and spread > 0.3 * sd:
            shape = _shape(cents, means)
            out.append(f"Residual by input level: mean residual ranges over {spread:.3g} "
                       f"(largest {worst[1]:+.3g} at e = {worst[0]:.3g}); {shape}")
        else:
            out.append("Residual by input level: no systematic trend with amplitude.")
    return out


def _shape(c, m) -> str:
    """Words for how the level-wise residual bends."""
    if len(c) < 3:
        return "few levels."
    edge = max(abs(m[0]), abs(m[-1]))
    mid = float(np.mean(np.abs(m[1:-1]))) if len(m) > 2 else 0.0
    if edge > 2.5 * mid and m[0] * m[-1] < 0 and m[-1] < 0:
        return ("the model overshoots the data at both extremes of the input: the "
                "output flattens at large amplitude (clipping or gain compression).")
    if m[-1] < 0 and m[0] > 0:
        return "the measured gain falls at large amplitude (gain compression)."
    return "the measured gain changes with the level (a nonlinearity)."


def _fails(t) -> str:
    return "; ".join(t.reasons) if t.reasons else "passes"


def verdict(causes, base, ext, tests, checks, evb, eva, pb, floor,
            ambiguous=()) -> list[str]:
    """Why these causes: the numbers that decided and the evidence they fix.
    `ambiguous`: sentences on effects left unnamed because the record cannot
    tell them apart (selection.forward), said first."""
    from . import guards
    out = list(ambiguous)
    fs = pb.setup.fs
    m = pb.setup.oversample
    if not causes:
        if not ambiguous:
            out.append("No effect is named: none passes every guard against the linear "
                       "model refitted with the same freedoms.")
        for t in sorted(tests, key=lambda t: t.model.nrmse_val)[:3]:
            out.append(f"{t.effect}: held-out NRMSE {t.ref.nrmse_val:.4f} -> "
                       f"{t.model.nrmse_val:.4f}, dBIC {t.dbic:+.1f}, largest contribution "
                       f"{t.peak:.2g} noise sd: {_fails(t)}.")
        if evb["ccf_out"] <= 2:
            out.append("The baseline's residual does not depend on the input: the linear "
                       f"model explains the data down to the noise (validation NRMSE "
                       f"{base.nrmse_val:.4f}, noise floor {floor:.4f}).")
        else:
            out.append(_unexplained(base, tests, floor))
        return out
    by = {t.effect: t for t in checks}
    p = ext.effect_params(pb.setup.fs_int, m)
    for c in causes:
        t = by.get(c)
        desc = describe_effect(c, p, fs)
        line = f"Cause: {c} at the {model.PLACE[c]}: {desc}"
        if t is not None:
            line += (f"; without it the held-out NRMSE is {t.ref.nrmse_val:.4f} (with it "
                     f"{t.model.nrmse_val:.4f}), dBIC {t.dbic:+.1f}, largest contribution "
                     f"{t.peak:.2g} noise sd")
        out.append(line + ".")
    out.append(f"Held-out NRMSE {base.nrmse_val:.4f} -> {ext.nrmse_val:.4f} "
               f"(noise floor {floor:.4f}).")
    named = set(causes)
    others = [t for t in sorted(tests, key=lambda t: t.model.nrmse_val) if t.effect not in named]
    if others:
        o = others[0]
        out.append(f"Best of the others on the baseline: {o.effect} ({o.model.nrmse_val:.4f} "
                   f"held-out): {_fails(o) if not o.passes else 'passes alone, but not once the named effects are in'}.")
    k = evb["early"]["lag_samples"] if evb["early"] else 0.0
    for c in causes:
        if c == "dead_time":
            out.append(f"Evidence: after steps the output answers {k:+.1f} samples late "
                       "against the baseline; a pure delay shifts the whole response without "
                       "changing its shape, which a lag or the relay's dynamics cannot mimic.")
        elif c == "lag":
            out.append("Evidence: the output's early response is rounded, not shifted; a "
                       "first-order lag on the line explains it, a pure delay does not.")
        elif c == "saturation":
            out.append("Evidence: the error sits at the extremes of the output range, where "
                       "the measured output is flat while the model keeps rising: p_c is "
                       "limited.")
        elif c == "backlash":
            mr, _ = _t(evb["rise"])
            mf, _ = _t(evb["fall"])
            out.append(f"Evidence: the baseline's error depends on the direction of the last "
                       f"step (rising {mr:+.3g}, falling {mf:+.3g}): the flapper stays put "
                       "until the input has crossed the dead band.")
        elif c == "nozzle":
            out.append("Evidence: the error grows smoothly with the input's amplitude, "
                       "without flat tops: the nozzle's gain changes away from its "
                       "operating point.")
    out.append(f"After the fix: the whitened residual leaves the 99 % band against the "
               f"input at {eva['ccf_out']} lags (was {evb['ccf_out']}).")
    return out


def _unexplained(base, tests, floor) -> str:
    """What a verdict without a cause says when the baseline's residual still
    depends on the input: the model misses something, by how much against
    the noise floor (the NRMSE the noise alone leaves), and why the effects
    that could be it were refused. "Not material" is said only when it is
    true: an effect significant and material on the fit part that fails
    only by predicting the held-out part, or by BIC, is a large effect the
    model places wrongly or cannot place alone (two at once, a held-out part
    at levels the fit part never reached), not a small one, and a record 9x
    above its floor reported as "nothing material" hides that."""
    big = [t.effect for t in sorted(tests, key=lambda t: t.model.nrmse_val)
           if t.significant and t.material]
    line = ("The model misses something it cannot name: the baseline's residual still "
            f"depends on the input, and its held-out NRMSE is {base.nrmse_val:.4f}"
            + (f", {base.nrmse_val / floor:.1f}x the noise floor {floor:.4f}" if floor > 0
               else f" (noise floor {floor:.4f})"))
    passed = [t.effect for t in tests if t.passes]
    if passed:       # passed every guard, left unnamed: imitators (the ambiguity above)
        return (line + f"; {', '.join(passed)} {'passes' if len(passed) == 1 else 'pass'} "
                "every guard but the record cannot tell which cause it is.")
    if not big:
        return line + "; no catalogued cause explains it materially."
    return (line + f"; {', '.join(big)} {'is' if len(big) == 1 else 'are'} significant and "
            "material on the fit part but refused by the held-out part or BIC: the catalogued "
            "causes, one at a time as the model places them, do not describe it.")


def describe_effect(cause: str, p: dict, fs: float) -> str:
    if cause == "dead_time":
        return (f"dead time {p['dead_time'] * 1e3:.4g} ms "
                f"({p['dead_time_samples']:g} samples)")
    if cause == "lag":
        return f"line lag {p['lag'] * 1e3:.4g} ms ({p['lag'] * fs:.2f} samples)"
    if cause == "saturation":
        kind = model.SAT_KINDS[model.sat_kind(p)]
        told = ("" if p.get("sat_kind_told") else
                " (the record does not tell this from the other placements)")
        return f"p_c limited to [{p['sat_lo']:.4g}, {p['sat_hi']:.4g}]: {kind}{told}"
    if cause == "backlash":
        return f"dead band {p['deadband']:.4g} input units wide"
    if cause == "nozzle":
        return f"nozzle x_1/2 = {p['nozzle_xh']:.4g} input units"
    return ""
