# SPDX-License-Identifier: MIT
"""How the fits search: many starts explored on a small copy of the record,
the best one refined on the whole fit part.

Every simulation costs in proportion to the record's length, but the shape
of an optimum is fixed long before the end of a long record. Starts are
ranked and explored on the exploration copy: the fit part block-averaged
down to about F_EXPLORE (a 10 kHz record by 10 to 1 kHz, the factor read
off the rate as every whole factor of it is: model.rate_multiple; the
groups are continuous-time, so they carry over) and cut to its first
N_EXPLORE samples at every rate. Only the best is refined on the whole fit
part, from the copy's optimum, a few iterations. Dead time, in samples of
the simulation rate, is converted between the two.

The copy is counted in samples, not in time or simulation steps: what a
start's rank rests on is the input's changes the copy holds, and a
record's changes are spaced in its samples as often as in seconds, so a
copy of a fixed duration would hold a tenth of them on a 100 Hz record
and rank its starts on that. The cost of a slow record (simulated at many
steps a sample) is bounded by data.MAX_SIM_STEPS instead. The measurements
behind both are in docs/analysis-bench.md (branches speed10, speed11)."""
from __future__ import annotations

import copy
import math

import numpy as np

from . import fit, model

N_EXPLORE = 6000           # samples of the exploration copy
F_EXPLORE = 1000.0         # Hz: records faster than this are block-averaged for it
STAGE_ITER = 10            # Jacobians per start and stage of the exploration
EXPLORE_ITER = 30          # Jacobians of a single exploring fit
REFINE_ITER = 10           # Jacobians per refining fit
# Where a fit replaces one already found and is called better (selection's
# tests and retests, saturation's placements), its cost must be lower by
# more than this fraction; where a search only keeps the lower fit
# (search.best) no such claim is made. It is below the relative cost change
# per step at which fit.lm_fit stops (ftol 1e-5), so it absorbs only part
# of what two runs that stop at the one optimum can differ by (a placement
# that ran longer can still take the name, marked not told); and it is no
# evidence of anything: in the deviance it is m ln(1 + 1e-6) = 0.1 on a 100 000-sample fit
# part (4 on the longest a fit takes, data.MAX_SIM_STEPS at one step a
# sample), where a guard's likelihood-ratio and BIC tests ask for more.
# Ties so broken keep the fit already found, not the one that ran longer.
COST_RTOL = 1e-6


def lower(cost: float, than: float) -> bool:
    """cost is lower than `than` by more than COST_RTOL: a fit that is
    called better than one already found (above)."""
    return cost < than * (1 - COST_RTOL)


def best(fits):
    return min(fits, key=lambda r: r.cost)


def _budget(pb, effects, iters: int) -> int:
    return iters * (len(fit.specs(pb, effects)) + 2)


def explorer(pb):
    """The exploration copy of pb, or None when pb is small enough."""
    from .data import MIN_SAMPLES
    D = max(1, math.floor(model.rate_multiple(pb.setup.fs / F_EXPLORE)))
    # The copy keeps at least the samples a record needs to be fit at all:
    # a short record at a high rate (250 samples at 200 kHz) was averaged
    # down to one sample, and the fit ended in a traceback.
    D = min(D, max(1, pb.nsim // MIN_SAMPLES))
    fs = pb.setup.fs / D
    m = model.auto_oversample(fs)
    if D == 1 and pb.nsim <= 1.3 * N_EXPLORE:
        return None
    take = int(min(pb.nsim // D, N_EXPLORE))
    n = take * D
    q = copy.copy(pb)
    q.e_abs = pb.e_abs[:n].reshape(take, D).mean(axis=1)
    q.y = pb.y[:n].reshape(take, D).mean(axis=1)
    q.setup = model.Setup(pb.setup.config, fs, take / fs, pb.setup.order, m)
    q.split = pb.split.scaled(D, take)
    q.burn = min(pb.burn // D, max(q.split.first_end // 2, 0))
    q.nm = None if D > 1 else pb.nm     # a noise model is of one sampling rate
    return q


def dead_to(pb_from, pb_to, dead: int) -> int:
    """A dead time in samples of pb_from's simulation rate, in pb_to's."""
    if not dead:
        return 0
    return max(1, int(round(dead * pb_to.setup.fs_int / pb_from.setup.fs_int)))


def rank_fresh(pb, effects, starts: list, n_keep: int, dead: int = 0) -> list:
    """The n_keep best fresh starts by their cost on the exploration copy."""
    w = explorer(pb) or pb
    d = dead_to(pb, w, dead)
    scored = sorted(((fit.start_cost(w, effects, st, d), i) for i, st in enumerate(starts)))
    return [starts[i] for c, i in scored[:n_keep] if math.isfinite(c)]


def _halving(w, effects, starts, dead, label_iters=None, trails=None):
    """Successive halving: every start gets STAGE_ITER iterations, the
    better half continues for another STAGE_ITER, and so on down to one,
    which runs a last stage. Most of the effort goes to the starts that
    lead somewhere. trails: {label: dict} for starts also fitted on their
    own from the same place (candidates._apart): every point of their
    first stage is added to their dict (fit.lm_fit's trail)."""
    label_iters = label_iters or STAGE_ITER
    # Each stage goes on from where the last stopped: the points of every
    # run's last Jacobian are kept for it (fit.lm_fit's memo; the copy is
    # small, a few MB for a whole halving).
    memo: dict = {}
    trails = trails or {}
    runs = [fit.lm_fit(w, effects, st, dead, _budget(w, effects, label_iters), lab, memo=memo,
                       trail=trails.get(lab))
            for lab, st in starts]
    while True:
        runs.sort(key=lambda r: r.cost)
        runs = runs[:max(1, (len(runs) + 1) // 2)]
        runs = [fit.lm_fit(w, effects, r.values, dead, _budget(w, effects, label_iters),
                           r.start, memo=memo) for r in runs]
        if len(runs) == 1:
            return runs[0]


def explore(pb, effects, starts: list, dead: int = 0, stage_iter: int = STAGE_ITER,
            w=None, trails=None):
    """The exploration of explore_refine: the best of the starts after
    successive halving on the exploration copy (w: pb's, when already
    made; trails: _halving's); None when pb has none."""
    if w is None:
        w = explorer(pb)
    if w is None:
        return None
    return _halving(w, model.canonical(effects), starts, dead_to(pb, w, dead), stage_iter,
                    trails)


def explore_refine(pb, effects, starts: list, dead: int = 0,
                   refine_iter: int = REFINE_ITER, stage_iter: int = STAGE_ITER,
                   explored=None):
    """Starts explored on the exploration copy by successive halving, the
    best refined on the whole fit part. Returns the best fit, evaluated.
    explored: explore's result for these arguments, when already made."""
    effects = model.canonical(effects)
    e = explored if explored is not None else explore(pb, effects, starts, dead, stage_iter)
    if e is None:               # no exploration copy: the halving on pb itself
        b = _halving(pb, effects, starts, dead, stage_iter)
    else:
        b = fit.lm_fit(pb, effects, e.values, dead, _budget(pb, effects, refine_iter), e.start)
    fit.evaluate(pb, b)
    return b


def refine(pb, effects, starts: list, dead: int = 0, iters: int = REFINE_ITER):
    """LM on the whole fit part from the best of (label, start) by its cost;
    evaluated."""
    effects = model.canonical(effects)
    if len(starts) > 1:
        costs = [fit.start_cost(pb, effects, st, dead) for _, st in starts]
        starts = [starts[int(np.argmin(costs))]]
    lab, st = starts[0]
    b = fit.lm_fit(pb, effects, st, dead, _budget(pb, effects, iters), lab)
    fit.evaluate(pb, b)
    return b
