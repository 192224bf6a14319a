# SPDX-License-Identifier: MIT
"""Extended models: a fitted model plus one more effect block of the
library, at its physical place, fitted from warm starts (the model's own
values, a few effect sizes) and fresh starts (random shapes), so that a
model stuck in a degenerate corner cannot trap the extension.

Dead time is a whole number of samples of the simulation rate: it is
profiled. It sits at the end of the output line, so the model's output
with a delay of d samples is its output without one, shifted by d: one
simulation scans every delay (K and pc0 re-solved for each), then the
groups are refitted at the best few."""
from __future__ import annotations

import copy
import math

import numpy as np

from . import fit, model, search

N_FRESH = 12
N_FRESH_KEEP = 1
DEAD_MAX = 200             # data samples scanned at most


def effect_inits(pb, effect: str) -> list[dict]:
    fs = pb.setup.fs
    if effect == "lag":
        return [{"lag": 2.0 / fs}, {"lag": 15.0 / fs}]
    if effect == "saturation":
        m = 0.02 * (pb.y_hi - pb.y_lo)
        return [{"sat_lo": pb.y_lo - m, "sat_hi": pb.y_hi + m},
                {"sat_lo": pb.y_lo + 5 * m, "sat_hi": pb.y_hi - 5 * m}]
    if effect == "backlash":
        return [{"deadband": 0.01 * pb.span_e}, {"deadband": 0.04 * pb.span_e}]
    if effect == "nozzle":   # at the inflection, and on either side of it
        return [{"nozzle_k": 0.3 / pb.amp_e, "nozzle_bias": 0.0},
                {"nozzle_k": 0.3 / pb.amp_e, "nozzle_bias": 0.6},
                {"nozzle_k": 0.3 / pb.amp_e, "nozzle_bias": -0.3}]
    return [{}]


def _sat_start(pb, base, st: dict) -> dict:
    """Saturation's limits are on the simulated deviation, before the
    offset: move the starts by the base's offset, and give K (searched,
    not solved, with saturation) the base's value."""
    st = dict(st)
    c = base.values.get("pc0", 0.0) - (pb.y[:10].mean() if pb.pc0 is None else pb.pc0)
    if "sat_lo" in st:
        st["sat_lo"] -= c
        st["sat_hi"] -= c
    st.setdefault("K", base.values["K"])
    return st


def with_freed(pb, groups: list):
    """The problem with some held groups freed again (at their held values)."""
    q = copy.copy(pb)
    q.fixed = {k: v for k, v in pb.fixed.items() if k not in groups}
    q.free = list(pb.free) + [g for g in groups if g not in pb.free]
    return q


def _paper_shape(pb, full: dict) -> dict:
    """full with every free group but K at the paper's value."""
    nom = model.nominal_groups(pb.setup.config)
    out = dict(full)
    out.update({g: nom[g] for g in pb.free if g in nom and g != "K"})
    return out


def _starts(pb, effects, new: str, base, rng, hint: dict | None = None):
    """Warm starts (base values, each effect size). On the linear model
    also the paper's values and the best fresh start: the baseline may sit
    in a corner that the new effect gets it out of. On a model that already
    has effects, the size this effect took in the previous round (hint)."""
    full = {**base.groups, **base.values}    # held groups that pb frees included
    inits = effect_inits(pb, new)
    if hint:
        inits = [hint] + inits
    warm = []
    for i, ei in enumerate(inits):
        st = dict(full)
        st.update(ei)
        if "saturation" in effects:
            st = _sat_start(pb, base, st)
        warm.append((f"warm{i}", st))
    if base.effects:
        return warm
    paper = _paper_shape(pb, full)
    paper.update(inits[0])
    if "saturation" in effects:
        paper = _sat_start(pb, base, paper)
    warm.append(("paper", paper))
    fresh = []
    for j, g in enumerate(fit.random_starts(pb, rng, N_FRESH)):
        st = dict(full)
        g.pop("K", None)                 # solved, or (saturation) the base's
        st.update(g)
        st.update(inits[j % len(inits)])
        if "saturation" in effects:
            st = _sat_start(pb, base, st)
        fresh.append(st)
    kept = search.rank_fresh(pb, effects, fresh, N_FRESH_KEEP, base.dead)
    return warm + [(f"fresh{i}", s) for i, s in enumerate(kept)]


def scan_dead(pb, effects, vals: dict, dmax: int) -> list[tuple[float, int]]:
    """(cost, d) for every delay d = 0..dmax samples of the simulation rate,
    from one simulation shifted (K and pc0 re-solved per delay)."""
    m = pb.setup.oversample
    g = fit._groups(pb, vals)
    sK = fit.solves_K(pb, effects)
    if sK:
        g["K"] = 1.0
    ev = dict(vals)
    ev["dead"] = 0
    e = pb.e_abs[:pb.nfit] - g["e0"]
    raw = pb.setup.simulate(g, e, tuple(x for x in effects if x != "dead_time"), ev,
                            internal=True)
    out = []
    for d in range(0, dmax + 1):
        sh = np.concatenate([np.zeros(d), raw[:raw.size - d]])[::m]
        K, c = fit.project(pb, sh, sK, 1.0, pb.counted)
        if sK and not K > 0:
            continue
        r = fit.whiten(pb, (K * sh + c if sK else sh + c)[pb.counted] - pb.y[pb.counted])
        out.append((float(r @ r), d))
    out.sort()
    return out


def _dead_candidates(pb, effects, base) -> list[int]:
    m = pb.setup.oversample
    dmax = int(min(DEAD_MAX, pb.nfit // 20)) * m
    scan = scan_dead(pb, effects, {**base.groups, **base.values}, dmax)
    top = [d for _, d in scan[:3] if d >= 1]
    # The data's own answer: the relay passes 1/rho of a step at once, so
    # the output's increments correlate with the input's at the delay.
    n = pb.nfit
    dy = np.diff(pb.y[:n])
    de = np.diff(pb.e_abs[:n])
    cc = [abs(float(dy[k:] @ de[:de.size - k])) for k in range(0, dmax // m + 1)]
    d_cc = int(np.argmax(cc)) * m
    cand = set(top)
    if d_cc >= 1:
        cand.add(d_cc)
    return sorted(cand) or [m]


def fit_extended(pb, base, new: str, rng, hint: dict | None = None):
    """base's effects plus `new`, from warm and fresh starts, explored and
    refined (search.explore_refine); dead time profiled first. hint: the
    new effect's parameters fitted in an earlier round."""
    effects = model.canonical(base.effects + (new,))
    if new == "dead_time":
        ds = _dead_candidates(pb, effects, base)
        if hint and hint.get("dead"):
            ds = sorted(set(ds) | {int(hint["dead"])})
        full = {**base.groups, **base.values}
        w = search.explorer(pb) or pb
        budget = search._budget(w, effects, search.STAGE_ITER)
        # each delay from the model so far and, when that is the linear
        # baseline (possibly in a corner that mimics the delay), from the
        # paper's values too
        shapes = [("", full)] + ([("paper ", _paper_shape(pb, full))] if not base.effects else [])
        # the copy's delays on either side of each candidate (its samples
        # are coarser), explored from each shape by successive halving
        r = w.setup.fs_int / pb.setup.fs_int
        dws = sorted({max(1, f(d * r)) for d in ds for f in (math.floor, math.ceil)})
        tried = [(fit.lm_fit(w, effects, st, dw, budget, f"{lab}d={dw}"), dw)
                 for dw in dws for lab, st in shapes]
        if not base.effects:          # and one fresh start at the best delay
            e, dw = min(tried, key=lambda x: x[0].cost)
            for lab, st in _starts(pb, effects, new, base, rng)[-1:]:
                tried.append((fit.lm_fit(w, effects, st, dw, budget, lab), dw))
        while len(tried) > 1:
            tried.sort(key=lambda x: x[0].cost)
            tried = [(fit.lm_fit(w, effects, e.values, dw, budget, e.start), dw)
                     for e, dw in tried[:(len(tried) + 1) // 2]]
        e, dw = tried[0]
        d = max(1, int(round(dw / r)))
        b = search.refine(pb, effects, [(e.start, e.values)], dead=d)
        fits = [b]
        # The shape moves with the delay (a baseline mimics part of a delay
        # with its own dynamics): scan the delay again with the refined
        # shape, refit where it points, until it stays put.
        dmax = int(min(DEAD_MAX, pb.nfit // 20)) * pb.setup.oversample
        for _ in range(8):
            scan = scan_dead(pb, effects, {**b.groups, **b.values}, dmax)
            d_new = next((dd for _, dd in scan if dd >= 1), b.dead)
            if d_new == b.dead:
                break
            b = search.refine(pb, effects, [(f"d={d_new}", dict(b.values))], dead=d_new)
            fits.append(b)
        b = search.best(fits)
        for dd in (b.dead - 1, b.dead + 1):
            if dd >= 1 and all(f.dead != dd for f in fits):
                fits.append(search.refine(pb, effects, [(f"d={dd}", dict(b.values))],
                                          dead=dd, iters=search.REFINE_ITER // 2))
        return search.best(fits)
    return search.explore_refine(pb, effects, _starts(pb, effects, new, base, rng, hint),
                                 dead=base.dead)
