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
import dataclasses
import math

import numpy as np

from . import baseline, digest, fit, guards, lib, model, noise, placement_share, search

N_FRESH = 12
N_FRESH_KEEP = 1
DEAD_MAX = 200             # data samples scanned at most
CORNER = "corner freed"    # the label of the start corner_freed makes


# Relative cost of testing an effect: an effect inside the loop (a play,
# the nozzle curve, the supply limits) makes the library solve the loop
# iteratively at every sample, 3-4x the cost of a linear simulation, and
# the nozzle has two parameters and three starting sizes; saturation is
# fitted at its three placements.
COST = {"nozzle": 4, "backlash": 3, "saturation": 9, "dead_time": 1, "lag": 1}


def by_cost(tasks: list) -> list:
    """(pb, model, effect, ...) tasks, costliest effect first: scheduled in
    that order, no long test is left to run alone at the end."""
    return sorted(tasks, key=lambda t: -COST.get(t[2], 1))


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


def no_effect(pb, effect: str) -> dict:
    """The effect's parameters at (or, for the lag, next to) no effect: the
    model without it, nested in the model with it. Dead time has none (it
    is at least one sample)."""
    if effect == "lag":
        return {"lag": 0.02 / pb.setup.fs}       # its lower bound (fit._effect_specs)
    if effect == "saturation":                   # limits beyond anything the output reaches
        span = pb.y_hi - pb.y_lo
        return {"sat_lo": pb.y_lo - span, "sat_hi": pb.y_hi + span}
    if effect == "backlash":
        return {"deadband": 0.0}
    if effect == "nozzle":
        return {"nozzle_k": 0.0, "nozzle_bias": 0.0}
    return {}


def _sat_shift(pb, base) -> float:
    """The record's output deviation minus the simulated one, at the same
    output: saturation's limits on the simulated deviation are the
    record's, less this."""
    return base.values.get("pc0", 0.0) - (pb.y[:10].mean() if pb.pc0 is None else pb.pc0)


def on_sim(pb, base, size: dict) -> dict:
    """An effect size in the record's terms (effect_inits, no_effect, and
    a size fitted in an earlier round as selection._hint gives it:
    saturation's limits on the record's output deviation) as a fit on top
    of base takes it: saturation's limits on the simulated deviation,
    before the offset, so less base's (_sat_shift). Only such sizes are
    moved. The model so far's own limits, when it has saturation, are on
    its simulated deviation already: moving them again would start the
    model so far away from its own optimum, and the no-effect start of
    _not_worse away from the model it nests."""
    if "sat_lo" not in size:
        return size
    c = _sat_shift(pb, base)
    return {**size, "sat_lo": size["sat_lo"] - c, "sat_hi": size["sat_hi"] - c}


def with_kind(pb, kind: int, told: float = 0.0):
    """The problem with saturation placed as `kind` (model.SAT_KINDS), and
    whether the record told that placement from the other: every fit on it
    simulates that placement and names it (fit.finish)."""
    if (pb.setup.sat_kind, pb.setup.sat_kind_told) == (kind, told):
        return pb
    q = copy.copy(pb)
    q.setup = dataclasses.replace(pb.setup, sat_kind=kind, sat_kind_told=told)
    return q


def for_model(pb, fr):
    """The problem on which fr's model is refitted: its saturation where fr
    placed it (a refit's values come from the search's parameters alone)."""
    if fr is None or "saturation" not in fr.effects or "sat_kind" not in fr.values:
        return pb           # every fit names its placement (fit.finish)
    return with_kind(pb, model.sat_kind(fr.values), float(fr.values.get("sat_kind_told", 0.0)))


def _kind_told(pb_a, a, pb_b, b) -> bool:
    """Whether the record tells placement a from b: the rule that tells any
    two explanations apart (guards.distinguishable), residuals whitened by
    the AR model of a's (if a is the explanation, its residual is the
    noise)."""
    ta = guards.Test("saturation", a, None, nm=noise.fit(pb_a.fit_pieces(a.residual(pb_a))))
    tb = guards.Test("saturation", b, None)
    ta.pb, tb.pb = pb_a, pb_b
    return guards.distinguishable(ta, tb)


def _fit_saturation(pb, base, rng, hint):
    """Saturation at every placement the library has (model.SAT_KINDS: the
    relay's memory held on a limit, run on, or wound on), each from the
    same starts and with the same search: what a record's recovery from a
    limit looks like is not known in advance, so none is assumed; each
    then refined from the best one's optimum too (_from_best_placement).
    The best is kept, marked with its placement and with whether the record tells
    it from each of the others. Every guard then treats it as any fit of
    saturation."""
    effects = model.canonical(base.effects + ("saturation",))
    fits = []
    # the same fresh starts for all: the others' from copies of the generator
    kinds = (model.SAT_CLIP, model.SAT_STOP, model.SAT_WIND)
    rngs = {k: rng if k == model.SAT_CLIP else copy.deepcopy(rng) for k in kinds}
    same = _same_exploration(pb, kinds)
    # every simulation on which no limit acts is the same at each placement:
    # simulated once (placement_share)
    with placement_share.shared():
        for kind in kinds:
            pk = with_kind(pb, kind)
            if kind == kinds[0] or not same:
                starts = _starts(pk, effects, "saturation", base, rngs[kind], hint)
                corner = _corner_of(pk, effects, "saturation", base, hint)
                explored = _explore_corner(pk, effects, starts, corner, base.dead)
            if explored is None:
                # no exploration copy: the corner-freed and paper starts
                # explored on their own on pk itself, as for every other
                # effect and for the reference (explore_refine_corner)
                b = explore_refine_corner(pk, effects, starts, corner, base.dead)
            else:
                b = search.explore_refine(pk, effects, starts, dead=base.dead,
                                          explored=explored)
            b = _limits_back_in_range(pk, effects, base, b)
            fits.append((_not_worse(pk, effects, "saturation", base, b), pk, kind))
        fits = _from_best_placement(fits, effects, base)
    win, pw, kw = fits[0]
    # the search done, before any test: a limit parked at the edge of the
    # fit part's output is still a start from which a placement's or a
    # refinement's path can make it bind (the kink it puts in the cost), so
    # it is put out only now (on each placement, blind seed 6's
    # two-backlash-saturation-pid lost the lower limit its search reached
    # from there, and with it the dead band named on top)
    win = _unseen_limits_out(pw, effects, win)
    fits[0] = (win, pw, kw)
    told = all(_kind_told(pw, win, pl, lose) for lose, pl, _ in fits[1:])
    win.values["sat_kind_told"] = 1.0 if told else 0.0
    return win


def _from_best_placement(fits, effects, base):
    """fits [(fit, problem, placement)], in any order: each placement but
    the best refined from the best one's optimum too, the refined fit kept
    where it is lower by more than search.COST_RTOL; and again from each
    new best's, until the best stays, each pair once (as
    selection.refit_rivals): a best that another overtakes is refined from
    the new one's optimum in turn. Pairs are counted by placement: a best
    that comes back keeps the others refined from its earlier optimum, so a
    placement the record is told from (_kind_told) can still have stopped
    a little short of the best's final optimum. Sorted by cost, the best first; a
    placement replaces the best only when lower by COST_RTOL too: where no
    limit binds, every placement is the same model, and a refinement that
    only ran longer edges the best out by 1e-8 (review_blind5: the name then
    said which fit ran longer, not what the record shows).
    The placements share every parameter and differ only in what the relay
    remembers while a limit acts on it, so the best placement's optimum
    starts the others where the record's levels, gain and limits are
    already found; from their own starts a placement can stop on the far
    side of a kink a limit puts in the cost (blind seed 5's
    saturation-id-multisine-pink-5, which opens clipped: "wound on" from
    its own starts lost to "runs on" at cost 1470.1; from that optimum it
    reaches 1124.2 in the tool's own run, held-out NRMSE 0.126 -> 0.043,
    floor 0.035). Chosen by the fit part's cost only, as the placements
    are."""
    fits = sorted(fits, key=lambda f: f[0].cost)
    done = set()
    while True:
        win, _, wk = fits[0]
        todo = [i for i in range(1, len(fits)) if (fits[i][2], wk) not in done]
        if not todo:
            return fits
        st = {**win.groups, **win.values}
        for i in todo:
            fr, pk, kind = fits[i]
            done.add((kind, wk))
            alt = search.refine(pk, effects, [("best placement's optimum", st)], dead=base.dead)
            if search.lower(alt.cost, fr.cost):
                fits[i] = (alt, pk, kind)
        rest = sorted(fits[1:], key=lambda f: f[0].cost)
        if search.lower(rest[0][0].cost, win.cost):
            fits = rest[:1] + sorted([fits[0]] + rest[1:], key=lambda f: f[0].cost)
        else:
            fits = fits[:1] + rest


def _same_exploration(pb, kinds) -> bool:
    """Whether the placements share their starts and exploration: the
    exploration copy (search.explorer) is a problem of its own, which
    simulates saturation at the library's default placement whatever pb's,
    so where every placement has one and they are the same, the starts'
    ranking on it and the successive halving there are the same too (from
    the same fresh starts: _fit_saturation) and are made once."""
    ws = [search.explorer(with_kind(pb, k)) for k in kinds]
    return all(w is not None and w.setup == ws[0].setup for w in ws)


def _limits_back_in_range(pb, effects, base, b):
    """A limit that the search left beyond the record's output range never
    binds, so the cost does not depend on it (zero gradient): no search
    can bring it back, however much better a binding limit would fit. The
    way there is a matter of the starts (a change in the last digits of
    the model so far sends the same start to either side). Such a limit
    is put back inside the range, at the inner effect size of
    effect_inits, the other parameters as fitted, and refined from there;
    the better fit is kept (a limit that should not bind goes out again)."""
    c = _sat_shift(pb, b)        # b's limits are on b's simulated deviation
    inner = on_sim(pb, b, effect_inits(pb, "saturation")[1])
    st = dict(b.values)
    off = {"sat_lo": st["sat_lo"] + c < pb.y_lo, "sat_hi": st["sat_hi"] + c > pb.y_hi}
    if not any(off.values()):
        return b
    for k, out in off.items():
        if out:
            st[k] = inner[k]
    alt = search.refine(pb, effects, [("limit back in range", st)], dead=base.dead)
    return search.best([b, alt])


# A limit the fit part does not show. Saturation's two limits are two
# parameters, and each must be identified by the fit part on its own: an
# upper limit that no fit sample reaches leaves the cost flat (the search
# parks it wherever the flat stretch begins, at the fit part's highest
# output, _limits_back_in_range's inner start included), and the held-out
# part then tests an extrapolation the fit part never determined: every
# excursion above the fit part's range is clipped (blind seed 9's
# two-backlash-saturation-pid-9: the tail reaches 13.9 above the opening
# level, the fit part 8.7; a limit at 8.4 cost the fit part 0.05 in 396
# and predicted the tail 8x worse, branch blind9). The test is the one the
# guards put to an effect, to each limit alone: the model with the limit
# against the same model with that limit out at no effect (no_effect),
# K and pc0 re-solved, the rest as fitted (guards._lr, in the criterion
# the fits minimised): a limit whose ratio is below the chi-square(1)
# 95 % point is not significant on the fit part. (Held, not profiled: a
# refit of the rest without the limit could only lower the cost without
# it, so the held ratio is the larger in the whitened criterion; with a
# model of the residual its normaliser moves a little with the limit.)
# Significance alone decides, not the guards' materiality (a noise sd
# somewhere): that is whether an effect is worth naming, not whether a
# parameter is identified. A true limit that clips the fit part's top
# plateaus by under a noise sd, on many samples, is fitted at its place
# and significant, and put out it would leave the far tail unclipped
# (a record built so: held-out NRMSE 0.16 -> 22; review of sat33, stop
# 34). A limit that fails the test is unidentified: the record says only
# that the output stays inside it wherever the fit part goes, so it is
# put at no effect (outside anything the fit part shows) and the rest
# refitted there, before any held-out test or report. Either limit, any
# split: the fit part alone decides. A limit that only the held-out part
# would show is, by the same token, not the fit part's to predict. What
# the test cannot do: tell a limit that absorbs the model's misfit (as
# significant on the fit part as a true one) from a true limit; the
# held-out test is the one that can.
def _limit_contribution(pb, effects, b, name: str):
    """b's output less its output with limit `name` at no effect (None
    when that model does not simulate)."""
    vals = {**b.values, name: on_sim(pb, b, no_effect(pb, "saturation"))[name]}
    try:
        y0, _, _, _ = fit.model_output(pb, effects, vals, b.dead)
    except lib.ModelError:
        return None
    d = b.sim - y0
    return d if np.all(np.isfinite(d)) else None


def limit_seen(pb, b, d) -> bool:
    """Whether fit b's limit whose contribution is d (_limit_contribution)
    is one the fit part shows (above): its likelihood ratio against that
    limit at no effect, the rest as fitted (K and pc0 re-solved), over the
    chi-square(1) 95 % point. d None (not simulated): no evidence against
    the limit."""
    if d is None:
        return True
    r1 = b.residual(pb)
    lr = guards._lr(pb, guards.noise_for(pb, r1), r1, r1 + d, d - float(np.mean(pb.fit_of(d))))
    return lr > guards.Z95 ** 2


def _unseen_limits_out(pb, effects, b):
    """b with each saturation limit the fit part does not show (above)
    put at no effect and the rest refitted there; b itself when both are
    shown. The refit is kept even at a higher cost: that limit's place is
    not the record's to give. A limit that acts on no fit sample at all
    changes nothing the fit part holds: moved without a refit."""
    out = on_sim(pb, b, no_effect(pb, "saturation"))
    st = dict(b.values)
    moved, grazes = [], False
    for name in ("sat_lo", "sat_hi"):
        if (st[name] <= out[name]) if name == "sat_lo" else (st[name] >= out[name]):
            continue                        # at no effect already
        d = _limit_contribution(pb, effects, b, name)
        if limit_seen(pb, b, d):
            continue
        st[name] = out[name]
        moved.append(name)
        grazes = grazes or bool(np.any(pb.fit_of(d)))
    if not moved:
        return b
    if grazes:
        return search.refine(pb, effects, [("limit not seen, out", st)], dead=b.dead)
    nb = copy.copy(b)
    nb.values = st
    fit.evaluate(pb, nb)
    return nb


def unseen_limits(pb, fr) -> list[str]:
    """The saturation limits of fr (the model reported), by name, that the
    fit part does not show (limit_seen, the rule of _unseen_limits_out):
    the record does not say where, or whether, the output is limited on
    that side."""
    if "saturation" not in fr.effects:
        return []
    return [name for name in ("sat_lo", "sat_hi")
            if not limit_seen(pb, fr, _limit_contribution(pb, fr.effects, fr, name))]


def limit_notes(pb, unseen: list[str]) -> list[str]:
    """Plain words for each limit the fit part does not show (unseen, the
    answer of unseen_limits)."""
    side = {"sat_lo": "lower", "sat_hi": "upper"}
    return [f"saturation: no {side[name]} limit is seen. The fit part's output stays "
            f"within {pb.y_lo:.4g} to {pb.y_hi:.4g} of the operating point and no "
            f"{side[name]} limit acts on the model's output there significantly, so the "
            f"model's is put beyond that range, where it clips nothing the fit part "
            f"shows: the {name} reported is not the record's, and where, or whether, "
            "the output is limited on that side the record does not say."
            for name in unseen]


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


def corner_freed(pb, base) -> tuple[dict, list[str]] | None:
    """_corner_freed, made once for each problem and model so far: every
    test of a round and its confirmation ask for it of the same two (the
    round's problem: selection.run_round makes it before its workers fork,
    and they inherit it here, _corner_key the same in both). A placement of saturation is read by no
    simulation of a model without saturation (model.library_effects,
    fit.finish), so on such a model the problems of saturation's three
    placements are one problem: the clip's."""
    if "saturation" not in base.effects:
        pb = with_kind(pb, model.SAT_CLIP)
    key = _corner_key(pb, base)
    if key not in _CORNERS:
        if len(_CORNERS) >= CORNERS_KEPT:
            _CORNERS.clear()
        _CORNERS[key] = _corner_freed(pb, base)
    return copy.deepcopy(_CORNERS[key])


# _corner_freed's answers by _corner_key, in this process (and the workers
# it forks); a diagnosis asks for a few per round
_CORNERS: dict = {}
CORNERS_KEPT = 64


def _corner_key(pb, base) -> bytes:
    """A digest of everything _corner_freed reads: the problem whole (its
    data, split, freedoms, noise model and setup: every attribute) and the
    model so far's effects, groups, values and delay. Equal digests, equal
    inputs, the same answer; a problem that differs in anything at all,
    even in what the answer does not depend on, is only made again (of
    the values, digest.of: the same in a worker as in its parent), and the
    package's settings (digest.settings, as the whole-fit cache: a setting
    changed at run time is not answered with a corner freed under the old
    one)."""
    return digest.of(pb, tuple(base.effects), {**base.groups, **base.values}, base.dead,
                     digest.settings(__package__))


def _corner_freed(pb, base) -> tuple[dict, list[str]] | None:
    """The model so far (base: its groups and values, the groups pb frees
    included) with every group that sits at a bound of its range
    (baseline.at_edges: free there, or held there by the baseline and freed
    by pb) put back inside, and the others refitted around them; with the
    groups moved. None when no group is at a bound. A group goes to the
    paper's value, or, where that is itself at an edge or outside the
    range, two restart steps inside (baseline.moved_inside: x9 for a log
    group, 0.3 for an order); a group that neither puts strictly inside
    its range (pid's w beside a nu near 1, say) stays. The others are refitted (the model so far,
    the moved groups held, on the exploration copy) so that the start is a
    fit, not a jump that the first stage of the search drops. The model
    WITHOUT the effect put those groups at the bound; the model with it may
    want them anywhere, and a search started only from that corner may stay
    there (docs/analysis.md, "A corner freed")."""
    full = {**base.groups, **base.values}
    edges = baseline.at_edges(pb, full)
    if not edges:
        return None
    nom = model.nominal_groups(pb.setup.config)
    moved = {}
    for name, _, side, lo, hi in edges:
        v = nom[name]
        if not lo < v < hi or any(e[0] == name for e in baseline.at_edges(pb, {**full, name: v})):
            v = baseline.moved_inside(name, side, lo if side == "lower" else hi, 2)
        v = baseline.keep_order(pb.setup.config, name, v, {**full, **moved})
        if lo < v < hi:
            moved[name] = v
    if not moved:
        return None
    held = copy.copy(pb)
    held.fixed = {**pb.fixed, **moved}
    held.free = [g for g in pb.free if g not in moved]
    w = search.explorer(held) or held
    st = {k: v for k, v in full.items() if k not in moved}
    try:
        r = fit.lm_fit(w, base.effects, st, search.dead_to(pb, w, base.dead),
                       search._budget(w, base.effects, search.EXPLORE_ITER), "corner freed")
        refit = r.values if math.isfinite(r.cost) else {}
    except lib.ModelError:      # the library refuses the moved groups beside the others
        refit = {}              # moved, the others as they were (corner_start checks it)
    return {**full, **refit, **moved}, list(moved)


def corner_start(pb, effects, base, size: dict):
    """The labelled start corner_freed makes of the model so far, with the
    effect at `size`; None without a corner."""
    cf = corner_freed(pb, base)
    if cf is None:
        return None
    st = dict(cf[0])
    st.update(size)          # on the simulated deviation already (_sizes)
    # a start the library refuses (its groups make no valid controller: a
    # gain the refit left invalid, say) is no start: the search would stop on it
    if not math.isfinite(fit.start_cost(pb, effects, st, base.dead)):
        return None
    return (f"{CORNER} (" + ", ".join(cf[1]) + ")", st)


def corner_notes(rounds, causes) -> list[str]:
    """Plain words for every named effect whose fit in a round came from the
    corner-freed start (corner_freed): the search from the model so far's
    corner alone would have found a worse optimum of it."""
    out = []
    for n, tests in enumerate(rounds, 1):
        for t in tests:
            lab = getattr(t.model, "start", "") or ""
            if t.effect in causes and lab.startswith(CORNER):
                groups = lab[len(CORNER):].strip(" ()")
                out.append(f"{t.effect} (round {n}) was fitted best from a start with the "
                           f"model so far's groups at a bound of their range ({groups}) put "
                           "back inside (at the paper's values or steps inside the bound, the "
                           "other groups refitted): the "
                           "model without it sat in that corner; the model with it fits "
                           "better away from it. Its gain is measured against the model "
                           "without it refitted with the same freedoms, its confirmation "
                           "searched from the same corner freed.")
    return out


def _sizes(pb, new: str, base, hint: dict | None) -> list[dict]:
    """The new effect's starting sizes, on the simulated deviation
    (on_sim): effect_inits; in a later round one, the size it took in the
    round before (hint) or the first."""
    inits = [on_sim(pb, base, s) for s in effect_inits(pb, new)]
    if base.effects:
        return [on_sim(pb, base, hint)] if hint else inits[:1]
    return inits


def _corner_of(pb, effects, new: str, base, hint: dict | None = None):
    """corner_start with the new effect at its first starting size."""
    return corner_start(pb, effects, base, _sizes(pb, new, base, hint)[0])


# Effects whose size the linear groups trade off against: a dead band
# drops the first part of every move after a reversal, which a lower gain
# and a slower reset imitate, so at the model so far's groups (fitted
# without the band) a wider band costs more than a narrower one, and a
# joint search from there shrinks the width before the groups can follow.
# The profile likelihood's remedy: the groups fitted first with the size
# held (fit.Problem.held), then the joint fit from there. On the whole fit
# part: the exploration copy (search.explorer: fewer samples, a coarser
# rate) need not hold the reversals that show the band, and its halving
# then picks the narrow band before the whole part is seen (blind seed 7's
# two-dead_time-backlash-id: 0.0071 at a cost of 79.0, above its own
# reference's 78.1; with the groups refitted at 0.020 held, the joint fit
# reaches 0.066 at 63.4, from 0.040 and 0.056 the same; branches blind7,
# two31). Dead time is profiled already (_fit_extended).
PROFILED = ("backlash",)


def _groups_moved(pb, effects, new: str, base, hint: dict | None):
    """The joint fit on pb from the model so far with the linear groups
    refitted at the new effect's first starting size held (_sizes)."""
    size = _sizes(pb, new, base, hint)[0]
    st = {**base.groups, **base.values, **size}
    q = copy.copy(pb)
    q.held = {**pb.held, **size}
    r = fit.lm_fit(q, effects, st, base.dead, search._budget(q, effects, search.STAGE_ITER),
                   "groups moved")
    return search.refine(pb, effects, [("groups moved", {**st, **r.values, **size})], base.dead)


def _starts(pb, effects, new: str, base, rng, hint: dict | None = None):
    """Warm starts (the model so far with each effect size, _sizes), the
    paper's values and the best fresh start: the model so far may sit in a
    basin that the new effect needs to get out of. The corner-freed start
    (_corner_of) is made apart: it is explored on its own (_corner_fit)."""
    full = {**base.groups, **base.values}    # held groups that pb frees included
    inits = _sizes(pb, new, base, hint)
    warm = []
    for i, ei in enumerate(inits):
        st = dict(full)
        st.update(ei)
        warm.append((f"warm{i}", st))
    paper = _paper_shape(pb, full)
    paper.update(inits[0])
    warm.append((baseline.PAPER, paper))
    fresh = []
    for j, g in enumerate(fit.random_starts(pb, rng, N_FRESH)):
        st = dict(full)
        g.pop("K", None)                 # solved, or (saturation) the base's
        st.update(g)
        st.update(inits[j % len(inits)])
        fresh.append(st)
    kept = search.rank_fresh(pb, effects, fresh, N_FRESH_KEEP, base.dead)
    return warm + [(f"fresh{i}", s) for i, s in enumerate(kept)]


def scan_dead(pb, effects, vals: dict, dmax: int) -> list[tuple[float, int]]:
    """(cost, d) for every delay d = 0..dmax samples of the simulation rate,
    sorted, from one simulation: with d = q m + p (m the oversampling), the
    delayed output at the data samples is the p-th phase of the internal
    output shifted by q data samples, and the whitening filter (FIR)
    commutes with the shift, so every cost follows from sliding sums and
    one dot product per delay (K and pc0 re-solved for each)."""
    from scipy.signal import lfilter
    m = pb.setup.oversample
    g = fit._groups(pb, vals)
    sK = fit.solves_K(pb, effects)
    if sK:
        g["K"] = 1.0
    ev = dict(vals)
    ev["dead"] = 0
    n = pb.nsim
    raw = pb.setup.simulate(g, pb.e_abs[:n] - g["e0"],
                            tuple(x for x in effects if x != "dead_time"), ev, internal=True)
    A = pb.nm.a if pb.nm is not None else np.array([1.0])
    o = A.size - 1
    # the whitened samples counted: each fit part's from its (o+1)-th on,
    # where the filter reads that part only
    spans = [(s.start + o, s.stop) for s in pb.fit_parts if s.stop > s.start + o]
    rows = np.concatenate([np.arange(a, b) for a, b in spans]) if spans else np.zeros(0, int)
    y = pb.y[:n] - (pb.pc0 if pb.pc0 is not None else 0.0)
    wy = lfilter(A, [1.0], y)[rows]
    w1 = lfilter(A, [1.0], np.ones(n))[rows] if pb.pc0 is None else None
    yy = float(wy @ wy)
    b1 = float(w1 @ w1) if w1 is not None else 0.0
    y1 = float(wy @ w1) if w1 is not None else 0.0
    qmax = dmax // m + 1
    out = []
    for p in range(m):
        u = raw[::m] if p == 0 else np.concatenate([[0.0], raw[m - p::m]])[:n]
        fw = np.concatenate([np.zeros(qmax), lfilter(A, [1.0], u)])
        c2 = np.concatenate([[0.0], np.cumsum(fw * fw)])
        c1 = np.concatenate([[0.0], np.cumsum(fw)])
        for q in range(qmax + 1):
            d = q * m + p
            if d > dmax:
                break
            sh = qmax - q
            ws = fw[rows + sh]
            ss = sum(c2[b + sh] - c2[a + sh] for a, b in spans)
            sy = float(ws @ wy)
            s1 = (sum(c1[b + sh] - c1[a + sh] for a, b in spans)
                  * (w1[-1] if w1 is not None and w1.size else 0.0))
            if sK:
                if w1 is None:
                    if not ss > 0:
                        continue
                    K = sy / ss
                    rss = yy - K * sy
                else:
                    det = ss * b1 - s1 * s1
                    if not det > 1e-12 * max(ss * b1, 1e-300):
                        continue
                    K = (sy * b1 - y1 * s1) / det
                    c = (ss * y1 - s1 * sy) / det
                    rss = yy - K * sy - c * y1
                if not K > 0:
                    continue
            else:
                rss = yy - 2 * sy + ss
                if w1 is not None:
                    rss -= (y1 - s1) ** 2 / b1
            out.append((max(float(rss), 0.0), d))
    out.sort()
    return out


def dead_max(pb) -> int:
    """The longest dead time scanned, in simulation samples: DEAD_MAX data
    samples, and at most a twentieth of the fit part (a delay must leave
    the fit part most of its samples)."""
    return int(min(DEAD_MAX, pb.split.n_fit // 20)) * pb.setup.oversample


def _dead_candidates(pb, effects, base) -> list[int]:
    m = pb.setup.oversample
    dmax = dead_max(pb)
    scan = scan_dead(pb, effects, {**base.groups, **base.values}, dmax)
    top = [d for _, d in scan[:3] if d >= 1]
    # The data's own answer: the relay passes 1/rho of a step at once, so
    # the output's increments correlate with the input's at the delay.
    # over the fit parts only: no held-out output reaches the fit's choices
    dys = [np.diff(pb.y[s]) for s in pb.fit_parts]
    des = [np.diff(pb.e_abs[s]) for s in pb.fit_parts]
    cc = [abs(sum(float(dy[k:] @ de[:de.size - k]) for dy, de in zip(dys, des) if de.size > k))
          for k in range(0, dmax // m + 1)]
    d_cc = int(np.argmax(cc)) * m
    cand = set(top)
    if d_cc >= 1:
        cand.add(d_cc)
    return sorted(cand) or [m]


def profile_dead(pb, effects, b):
    """b (a fit with dead time) with its delay profiled again: the shape
    moves with the delay (a model mimics part of a delay with its own
    dynamics), so the delay is scanned again with b's shape and refitted
    where it points, until it stays put, then its neighbours are tried."""
    fits = [b]
    dmax = dead_max(pb)
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


def fit_extended(pb, base, new: str, rng, hint: dict | None = None):
    """base's effects plus `new`, from warm and fresh starts, explored and
    refined (search.explore_refine); dead time profiled first. hint: the
    new effect's parameters fitted in an earlier round. On a model with a
    dead time the delay is profiled again with the new effect, as in the
    reference without it (selection.reference): a new timing effect (a lag)
    could otherwise stand in for the rest of a delay found short, with a
    reference held at the short delay. Saturation's limits, the model so
    far's or new, that the fit part does not show are put at no effect
    (_unseen_limits_out): any effect's search can park one (a new
    saturation's on the placement kept already, _fit_saturation)."""
    b = _fit_extended(pb, base, new, rng, hint)
    profiled = new != "dead_time" and "dead_time" in base.effects
    if profiled:
        b = profile_dead(for_model(pb, b), b.effects, b)
    if "saturation" in b.effects and (new != "saturation" or profiled):
        b = _unseen_limits_out(for_model(pb, b), b.effects, b)
    return b


def _fit_extended(pb, base, new: str, rng, hint: dict | None = None):
    effects = model.canonical(base.effects + (new,))
    if new == "saturation":
        return _fit_saturation(pb, base, rng, hint)
    pb = for_model(pb, base)            # saturation stays where the model so far has it
    if new == "dead_time":
        ds = _dead_candidates(pb, effects, base)
        if hint and hint.get("dead"):
            ds = sorted(set(ds) | {int(hint["dead"])})
        full = {**base.groups, **base.values}
        w = search.explorer(pb) or pb
        budget = search._budget(w, effects, search.STAGE_ITER)
        # each delay from the model so far and from the paper's values
        # (the model so far keeping its effects): a model fitted without
        # the delay mimics part of it with its own dynamics, a baseline in
        # a corner as much as a model with an effect (on a blind record with
        # saturation and a 9.1-sample delay, the saturation model's shape
        # alone led to 6.5 samples and a lag named for the rest)
        shapes = [("", full), ("paper ", _paper_shape(pb, full))]
        # the copy's delays on either side of each candidate (its samples
        # are coarser), explored from each shape by successive halving
        r = w.setup.fs_int / pb.setup.fs_int
        dws = sorted({max(1, f(d * r)) for d in ds for f in (math.floor, math.ceil)})
        # each delay's fits go on from where they stopped: the points of
        # their last Jacobians kept, one memo per delay (fit.lm_fit's memo)
        memo: dict = {dw: {} for dw in dws}
        tried = [(fit.lm_fit(w, effects, st, dw, budget, f"{lab}d={dw}", memo=memo[dw]), dw)
                 for dw in dws for lab, st in shapes]
        # at the best delay: the model so far with its corners put back
        # inside (where it has one: corner_freed), and in the first round
        # one fresh start
        e, dw = min(tried, key=lambda x: x[0].cost)
        if not base.effects:
            for lab, st in _starts(pb, effects, new, base, rng)[-1:]:
                tried.append((fit.lm_fit(w, effects, st, dw, budget, lab, memo=memo[dw]), dw))
        while len(tried) > 1:
            tried.sort(key=lambda x: x[0].cost)
            tried = [(fit.lm_fit(w, effects, e.values, dw, budget, e.start, memo=memo[dw]), dw)
                     for e, dw in tried[:(len(tried) + 1) // 2]]
        e, dw = tried[0]
        c = corner_start(pb, effects, base, {})
        if c is not None:
            e = search.best([e, _corner_fit(w, effects, c, dw)])
        d = max(1, int(round(dw / r)))
        b = profile_dead(pb, effects, search.refine(pb, effects, [(e.start, e.values)], dead=d))
        return _not_worse(pb, effects, new, base, b)
    b = explore_refine_corner(pb, effects, _starts(pb, effects, new, base, rng, hint),
                              _corner_of(pb, effects, new, base, hint), base.dead)
    if new in PROFILED:
        b = search.best([b, _groups_moved(pb, effects, new, base, hint)])
    return _not_worse(pb, effects, new, base, b)


def _explore_corner(pb, effects, starts, corner, dead: int = 0, stage: int = search.STAGE_ITER):
    """search.explore of the starts, and the corner-freed start (None: none)
    with the paper's values (_apart) each explored on its own beside them
    on the exploration copy: the best; None when pb has no exploration
    copy. Adding them never makes the halving's own winner worse: they only
    compete at the end."""
    apart = _apart(starts, corner)
    w = search.explorer(pb)
    trails = _trails(apart)
    e = search.explore(pb, effects, starts, dead, stage, w=w, trails=trails)
    if e is None or not apart:
        return e
    d = search.dead_to(pb, w, dead)
    return search.best([e] + [_corner_fit(w, effects, st, d, trails.get(st[0])) for st in apart])


def explore_refine_corner(pb, effects, starts, corner, dead: int = 0, **kw):
    """search.explore_refine of the starts, with the corner-freed start
    (corner_freed; None: none) and the paper's values (_apart) explored on
    their own beside their halving and the best refined (_corner_fit and
    _apart say why). The extended
    fit and, before an effect passes, its reference (selection.confirm)
    are searched this way, from the same place."""
    if corner is None:
        return search.explore_refine(pb, effects, starts, dead=dead, **kw)
    stage = kw.pop("stage_iter", search.STAGE_ITER)
    e = _explore_corner(pb, effects, starts, corner, dead, stage)
    if e is None:            # no exploration copy: the halving and the corner on pb itself
        apart = _apart(starts, corner)
        trails = _trails(apart)
        h = search._halving(pb, effects, starts, dead, stage, trails)
        b = search.best([h] + [_corner_fit(pb, effects, st, dead, trails.get(st[0]))
                               for st in apart])
        if b is not h:       # an exploring fit: refined, as the halving's stages were
            return search.refine(pb, effects, [(b.start, b.values)], dead=dead)
        fit.evaluate(pb, b)
        return b
    return search.explore_refine(pb, effects, starts, dead=dead, explored=e, **kw)


def _apart(starts, corner) -> list:
    """The starts explored on their own beside the halving of all of them:
    none without a corner (corner None). Where the model so far sits in a
    corner, the corner-freed start and the start at the paper's values are
    also explored on their own: the warm starts
    begin at the corner's own optimum, and the halving's first stage
    (search.STAGE_ITER Jacobians) ranks a start by how far it got, so a
    start that begins away from the corner is cut by warm starts that end
    worse. The paper start stays in the halving too, so the halving's own
    winner is what it was (taken out, it lost the lag of bench_fit's id@1k
    and pid@1k timing records, where it had won the halving: 5.8 ms for
    12 ms on id@1k). The paper's values are the one start that does not depend on
    the corner at all (the corner-freed start keeps the groups not at a
    bound as the corner left them). Traced on the own generator's pid lag
    (seed 132, held-out blocks, docs/analysis-bench.md "A split that covers
    the input's levels, as the default"): the baseline sits with L and rho
    near their upper bounds, tau at its lower; after the first stage the
    paper start's cost was behind the warm starts' and it was cut; the
    warm start won at a cost of 23.78 with a 4.6 ms lag in the corner,
    where 30 Jacobians from the paper's values alone reach 23.26 with
    16.5 ms (truth 18.6 ms)."""
    if corner is None:
        return []
    return [s for s in starts if s[0] == baseline.PAPER] + [corner]


def _trails(apart) -> dict:
    """{label: {}} for the starts in apart that the halving also runs (the
    paper's values; the corner-freed start is not among its starts): the
    halving's first stage from such a start is the beginning of its fit
    apart (_corner_fit), the same path (fit.lm_fit's trail), so its points
    are kept for that fit instead of simulated twice."""
    return {lab: {} for lab, _ in apart if not lab.startswith(CORNER)}


def _corner_fit(w, effects, start, dead: int, memo: dict | None = None):
    """The corner-freed start (corner_freed) explored on its own, as one
    exploring fit (search.EXPLORE_ITER Jacobians, about what the halving's
    winner gets), to compete with the halving's winner: inside the halving
    it is cut after the first stage by starts that begin nearer the model
    so far's optimum and end worse (blind record two-backlash-lag-pid-5s-1,
    backlash: after 40 Jacobians the corner-freed start's cost is 10.20,
    the warm start's 10.99, yet the halving kept the warm start)."""
    lab, st = start
    return fit.lm_fit(w, effects, st, dead, search._budget(w, effects, search.EXPLORE_ITER), lab,
                      memo=memo)


def _not_worse(pb, effects, new: str, base, b):
    """The model with the effect nests the model without it: a fit of it
    that ends worse than that model (the search lost on the way, as under
    strongly coloured noise, where the whitened criterion punishes a start's
    effect size hard and leaves the way to a small one flat) is refined
    again from the model so far with the effect at no effect (a dead time
    at its shortest), and the better of the two kept: every effect, the
    dead time too, so that no candidate is reported worse than the model
    it extends."""
    full = {**base.groups, **base.values}
    if not b.cost > fit.start_cost(pb, base.effects, full, base.dead):
        return b
    st = dict(full)
    st.update(on_sim(pb, base, no_effect(pb, new)))
    # a dead time has no no-effect value: its shortest, one sample of the
    # simulation rate, is the nearest to the model without it
    dead = 1 if new == "dead_time" else base.dead
    alt = search.refine(pb, effects, [("no-effect start", st)], dead=dead)
    return search.best([b, alt])
