# SPDX-License-Identifier: MIT
"""The diagnosis: baseline fit, what it gets wrong, the cause, the gain."""
from __future__ import annotations

import math
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from . import evidence as ev_mod
from . import fit, model
from .fit import FitResult, Problem

# Identified: the 95 % interval of a log group within a factor of 2 either
# way; of an order within +-0.15.
ID_LOG = math.log(2.0)
ID_LIN = 0.15
# The verdict needs both: BIC lower by more than 10 ("very strong" on
# Kass & Raftery's scale), and the held-out mean-square error lower by
# more than MIN_VAL_GAIN of the baseline's, so that a model error far below
# the noise (e.g. sampling-rate effects) is not mistaken for a cause.
MIN_DBIC = 10.0
MIN_VAL_GAIN = 0.05


class Progress:
    def __init__(self, enabled: bool = True):
        self.enabled = enabled
        self.t0 = time.monotonic()

    def __call__(self, msg: str) -> None:
        if self.enabled:
            print(f"[pneufrac-fit {time.monotonic() - self.t0:6.1f}s] {msg}",
                  file=sys.stderr, flush=True)


@dataclass
class Diagnosis:
    config: str
    fs: float
    n: int
    nfit: int
    baseline: FitResult
    extended: FitResult
    cause: str
    candidates: list
    identified: dict            # group -> True/False
    fixed_reason: dict          # group -> why it is held
    evidence: list              # strings
    why: list                   # strings: the verdict in words
    ev_before: dict = field(default_factory=dict)
    ev_after: dict = field(default_factory=dict)
    noise_sd: float = math.nan
    noise_floor_val: float = math.nan
    record_notes: list = field(default_factory=list)
    e: np.ndarray | None = None
    y: np.ndarray | None = None
    t: np.ndarray | None = None
    e0: float = 0.0
    pc0: float = 0.0
    elapsed: float = 0.0


# ------------------------------------------------------------- baseline fit
def _best(results):
    return min(results, key=lambda r: r.cost)


def _multistart(pb: Problem, effect: str, warm: list, rng, n_random: int,
                n_keep: int, budget: int, dead: int = 0, tag: str = ""):
    """LM from each warm start and from the best of n_random fresh starts."""
    fits = []
    for label, st in warm:
        fits.append(fit.lm_fit(pb, effect, st, dead, budget, label))
    if n_random > 0:
        scored = []
        einit = _effect_inits(pb, effect)
        for g in fit.random_starts(pb, rng, n_random):
            st = dict(g)
            st.update(einit[len(scored) % len(einit)] if einit else {})
            if "K" in pb.fixed:
                st.pop("K", None)
                scored.append((_cost(pb, effect, st, dead), st))
            else:
                st, c = fit.gain_solve(pb, effect, st, dead)
                scored.append((c, st))
        scored.sort(key=lambda s: s[0])
        for i, (_, st) in enumerate(scored[:n_keep]):
            fits.append(fit.lm_fit(pb, effect, st, dead, budget, f"fresh{i}"))
    return fits


def _cost(pb, effect, st, dead):
    try:
        r = fit.simulate(pb, effect, st, dead, pb.nfit) - pb.y[:pb.nfit]
        return float(r @ r)
    except Exception:
        return math.inf


def _effect_inits(pb: Problem, effect: str) -> list[dict]:
    fs = pb.setup.fs
    if effect == "lag":
        return [{"lag": 2.0 / fs}, {"lag": 8.0 / fs}, {"lag": 30.0 / fs}]
    if effect == "saturation":
        m = 0.02 * (pb.y_hi - pb.y_lo)
        return [{"sat_lo": pb.y_lo - m, "sat_hi": pb.y_hi + m},
                {"sat_lo": pb.y_lo + m, "sat_hi": pb.y_hi - m}]
    if effect == "backlash":
        return [{"deadband": 0.01 * pb.span_e}, {"deadband": 0.04 * pb.span_e}]
    if effect == "nozzle":
        return [{"nozzle_k": 0.1 / pb.amp_e}, {"nozzle_k": 0.4 / pb.amp_e}]
    return [{}]


def baseline_fit(pb: Problem, rng, say) -> tuple[FitResult, dict, dict]:
    """Multi-start fit of the linear model, then prune the groups the record
    does not determine (hold them at the paper's values) and refit."""
    nom = model.nominal_groups(pb.setup.config)
    start = {g: nom[g] for g in pb.free}
    start.update(fit.gain_solve(pb, "none", dict(start, **pb.fixed))[0] if "K" not in pb.fixed else {})
    start = {g: start[g] for g in pb.free}
    say(f"baseline: {len(pb.free)} groups free ({', '.join(pb.free)}), multi-start")
    fits = _multistart(pb, "none", [("paper", start)], rng, 24, 3, 60 * (len(pb.free) + 1))
    best = _best(fits)
    fixed_reason = {g: "fixed by --fix" for g in pb.fixed}
    identified = {}
    pb.entangled = []
    scale = float(np.std(pb.y[:pb.nfit]))
    while True:
        fit.uncertainty(pb, best)
        J = fit.jacobian(pb, best)
        sig2 = best.cost / pb.nfit
        worst, worst_ratio = None, 1.0
        for g in pb.free:
            tr = model.GROUPS[g][0]
            s = best.se.get(g, math.inf)
            ratio = 1.96 * s / (ID_LOG if tr == "log" else ID_LIN)
            if g != "K" and ratio > worst_ratio:
                worst, worst_ratio = g, ratio
        if worst is None:
            break
        i = best.free.index(worst)
        step = ID_LOG if model.GROUPS[worst][0] == "log" else ID_LIN
        visible = float(np.sum((J[:, i] * step * scale) ** 2)) > 10.0 * sig2
        val = best.groups[worst]
        pb.fixed[worst] = nom[worst]
        pb.free.remove(worst)
        if visible:
            pb.entangled.append(worst)
            why = "entangled with other groups"
        else:
            why = "no visible effect on this record"
        fixed_reason[worst] = (
            f"not identified ({why}; 95 % interval {_ci_text(worst, val, best.se[worst])}): "
            f"held at the paper's value {model.fmt_value(worst, nom[worst])}"
            + ("; freed again in the extended fits" if visible else ""))
        say(f"baseline: {worst} not identified ({why}); held at the paper's value")
        st = {g: best.groups[g] for g in pb.free}
        fits = [fit.lm_fit(pb, "none", st, 0, 60 * (len(pb.free) + 1), "pruned")]
        best = _best(fits)
    for g in model.CONFIG_GROUPS[pb.setup.config]:
        identified[g] = g in pb.free
    fit.evaluate(pb, best)
    return best, identified, fixed_reason


def _ci_text(name, val, se):
    tr = model.GROUPS[name][0] if name in model.GROUPS else "lin"
    if not math.isfinite(se) or (tr == "log" and 1.96 * se > 50):
        return "unbounded"
    if tr == "log":
        return f"x/ {math.exp(1.96 * se):.3g}"
    return f"+- {1.96 * se:.3g}"


# --------------------------------------------------------------- candidates
def fit_candidate(pb: Problem, effect: str, base: FitResult, seed: int) -> FitResult:
    """Extended model: the baseline's free groups plus the effect's own
    parameters, from warm and fresh starts (variant A). If the baseline had
    to hold groups that were entangled with others (the effect may be what
    entangled them), they are freed again from A's optimum (variant B), and
    BIC chooses between A and B."""
    import copy
    rng = np.random.default_rng(seed)
    warm_g = {g: base.groups[g] for g in pb.free}
    budget = 60 * (len(pb.free) + 3)
    if effect == "dead_time":
        a = _fit_dead_time(pb, base, warm_g, rng, budget)
    else:
        warm = [(f"warm{i}", dict(warm_g, **ei))
                for i, ei in enumerate(_effect_inits(pb, effect))]
        a = _best(_multistart(pb, effect, warm, rng, 16, 2, budget))
    fit.evaluate(pb, a)
    ent = [g for g in getattr(pb, "entangled", []) if g not in pb.user_fixed]
    best = a
    if ent:
        pbb = copy.copy(pb)
        pbb.fixed = {k: v for k, v in pb.fixed.items() if k not in ent}
        pbb.free = list(pb.free) + ent
        st = dict(a.values)
        st.update({g: pb.fixed[g] for g in ent})
        ds = [a.dead] if effect != "dead_time" else [a.dead, a.dead - 1, a.dead + 1]
        fits = [fit.lm_fit(pbb, effect, st, d, budget + 60 * len(ent), f"{a.start}+freed")
                for d in ds if effect != "dead_time" or d >= 1]
        b = _best(fits)
        b.variant = "B"
        fit.evaluate(pbb, b)
        if b.bic < a.bic - MIN_DBIC:   # the extra groups must earn their place
            best, pb = b, pbb
    fit.uncertainty(pb, best)
    best.problem_free = list(pb.free)  # type: ignore[attr-defined]
    return best


def _fit_dead_time(pb, base, warm_g, rng, budget):
    """Dead time is a whole number of samples: profile it. A scan with the
    baseline's shape (gain re-solved) brackets it, then the groups are refit
    at the best few delays, warm and fresh."""
    fs = pb.setup.fs
    dmax = int(min(200, pb.nfit // 20))
    scan = []
    for d in range(1, dmax + 1):
        st, c = fit.gain_solve(pb, "dead_time", dict(warm_g, **pb.fixed), d) \
            if "K" not in pb.fixed else (warm_g, _cost(pb, "dead_time", warm_g, d))
        scan.append((c, d))
    scan.sort()
    # The data's own answer: the relay passes 1/rho of a step at once, so
    # the output's increments correlate with the input's at the delay.
    dy = np.diff(pb.y[:pb.nfit])
    de = np.diff(pb.e[:pb.nfit])
    cc = [float(dy[d:] @ de[:de.size - d]) for d in range(0, dmax + 1)]
    d_cc = int(np.argmax(np.abs(cc)))
    cand = {scan[0][1], scan[1][1] if len(scan) > 1 else scan[0][1],
            scan[0][1] + 1, max(1, scan[0][1] - 1)}
    if d_cc >= 1:
        cand |= {d_cc, d_cc + 1, max(1, d_cc - 1)}
    ds = sorted(d for d in cand if 1 <= d <= dmax)
    fits = []
    for d in ds:
        fits.append(fit.lm_fit(pb, "dead_time", warm_g, d, budget, f"warm d={d}"))
    d0 = _best(fits).effect_params["dead_time_samples"]
    fits += _multistart(pb, "dead_time", [], rng, 16, 1, budget, dead=d0)
    best = _best(fits)
    # Fresh starts may move the shape; re-profile the delay around it once.
    d1 = best.effect_params["dead_time_samples"]
    for d in (d1 - 1, d1 + 1):
        if d >= 1 and d not in ds:
            fits.append(fit.lm_fit(pb, "dead_time", {g: best.groups[g] for g in pb.free},
                                   d, budget, f"refine d={d}"))
    return _best(fits)


def _run_candidate(args):
    pb, effect, base, seed = args
    t0 = time.monotonic()
    r = fit_candidate(pb, effect, base, seed)
    r.elapsed = time.monotonic() - t0  # type: ignore[attr-defined]
    return r


def fit_candidates(pb, base, say, jobs: int):
    # Longest first, so that two workers finish together.
    order = ["lag", "saturation", "backlash", "nozzle", "dead_time"]
    tasks = [(pb, c, base, 1000 + model.CAUSES.index(c)) for c in order]
    out = {}
    if jobs > 1:
        import multiprocessing as mp
        try:
            ctx = mp.get_context("fork")
        except ValueError:
            ctx = None
        if ctx is not None:
            pb.progress = None
            with ctx.Pool(jobs) as pool:
                for r in pool.imap_unordered(_run_candidate, tasks):
                    say(f"candidate {r.effect}: val NRMSE {r.nrmse_val:.4f}, "
                        f"BIC {r.bic:.1f} ({r.elapsed:.1f} s)")
                    out[r.effect] = r
            return [out[c] for c in model.CAUSES]
    for t in tasks:
        r = _run_candidate(t)
        say(f"candidate {r.effect}: val NRMSE {r.nrmse_val:.4f}, BIC {r.bic:.1f} "
            f"({r.elapsed:.1f} s)")
        out[r.effect] = r
    return [out[c] for c in model.CAUSES]


# ----------------------------------------------------------------- verdict
def choose(base: FitResult, cands: list[FitResult]):
    """Lowest held-out error among the candidates that pass both guards."""
    mse_b = base.nrmse_val ** 2
    ok = []
    for c in cands:
        dbic = c.bic - base.bic
        gain = 1.0 - c.nrmse_val ** 2 / mse_b if mse_b > 0 else 0.0
        c.dbic = dbic            # type: ignore[attr-defined]
        c.val_gain = gain        # type: ignore[attr-defined]
        c.passes = dbic < -MIN_DBIC and gain > MIN_VAL_GAIN  # type: ignore[attr-defined]
        if c.passes:
            ok.append(c)
    if not ok:
        return None
    return min(ok, key=lambda c: c.nrmse_val)


def noise_estimate(y: np.ndarray, e: np.ndarray) -> float:
    """Sensor noise sd from second differences away from input changes
    (robust: median absolute deviation). Input changes are those of
    data.change_points, the same as for the operating point."""
    from .data import change_points
    d2 = y[2:] - 2 * y[1:-1] + y[:-2]
    near = np.zeros(y.size, bool)
    for k in change_points(e):
        near[max(0, k - 2):k + 12] = True
    d2 = d2[~near[1:-1]]
    if d2.size < 20:
        d2 = y[2:] - 2 * y[1:-1] + y[:-2]
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    return 1.4826 * mad / math.sqrt(6.0)


def diagnose(rec, config: str, fixes: dict | None = None, *, order: int = 8,
             oversample: int = 2, jobs: int | None = None, progress: bool = True,
             seed: int = 0) -> Diagnosis:
    t0 = time.monotonic()
    say = Progress(progress)
    pb = Problem.from_record(rec, config, fixes, order, oversample)
    pb.user_fixed = dict(fixes or {})
    rng = np.random.default_rng(seed)
    say(f"{rec.n} samples at {rec.fs:g} Hz, config {config}; fit on the first "
        f"{pb.nfit}, validate on the last {rec.n - pb.nfit}")
    base, identified, fixed_reason = baseline_fit(pb, rng, say)
    say(f"baseline: NRMSE fit {base.nrmse_fit:.4f}, validation {base.nrmse_val:.4f}")
    if jobs is None:
        jobs = min(2, os.cpu_count() or 1)
    cands = fit_candidates(pb, base, say, jobs)
    best = choose(base, cands)
    cause = best.effect if best is not None else "none"
    ext = best if best is not None else base
    sd = noise_estimate(pb.y, pb.e)
    n = pb.nfit
    sy = float(np.std(pb.y[n:]))
    floor = sd / sy if sy > 0 else math.inf
    evb = ev_mod.analyse(pb, base, sd)
    eva = ev_mod.analyse(pb, ext, sd)
    evidence = ev_mod.describe(evb, pb, sd, floor, base)
    why = ev_mod.verdict(cause, base, ext, cands, evb, eva, pb, floor)
    say(f"cause: {cause}")
    d = Diagnosis(config, rec.fs, rec.n, n, base, ext, cause, cands, identified,
                  fixed_reason, evidence, why, evb, eva, sd, floor, list(rec.notes),
                  pb.e, pb.y, rec.t, rec.e0, rec.pc0)
    d.elapsed = time.monotonic() - t0
    return d
