# SPDX-License-Identifier: MIT
"""The baseline: the paper's linear model fitted from many starts, kept out
of corners, and pruned to the groups the record determines.

Corner: a fit that ends with a group at a bound of its range (beta at 1,
tau at a tenth of a sample...). It is restarted with that group moved back
inside; if no restart finds a better interior optimum the group is held at
the bound (the data put it there: beta = 1 is an integer-order diaphragm,
q = 0 a linear spring), which keeps its singular column out of the
identifiability test of the others.

Pruning: a group whose 95 % interval (sandwich covariance under the
residual's noise model) is wider than a factor 2 (orders: +-0.15) is not
identified; the worst is held and the fit repeated: where the fit put it if
the record shows it but only in combination with others (entangled), at the
paper's value if moving it changes nothing the record shows.
"""
from __future__ import annotations

import math

import numpy as np

from . import fit, model, noise, search

ID_LOG = math.log(2.0)
ID_LIN = 0.15
N_FRESH = 24               # fresh starts ranked
N_FRESH_KEEP = 4           # ... of which explored
STAGE_ITER = 20            # the baseline is one fit: it gets twice the search
BOUND_EDGE = 1e-3          # of the transformed range: "at the bound"
# The report's "at its bound": a free group within this fraction of its
# (transformed) range of a bound: a factor 1.16 for tau at 1 kHz over a
# 5 s record (log range 1e-4..50 s), 0.0095 for an order (0.05..1). Wider
# than BOUND_EDGE, the restarts' test, which stays as it is so that no fit
# changes: a value this close to a bound has no two-sided 95 % interval
# inside the range unless it is identified to within 1 % of the range.
REPORT_EDGE = 0.01
VISIBLE = 10.0             # noise variances of RSS: a change the record shows
# The measured noise model weighs the fit only while it describes the fit's
# residual: the whitened residual's variance at most PREMISE x the noise's
# innovation variance (its sd twice the innovations'). Beyond that the
# model's own error, not the noise, fills the criterion.
PREMISE = 4.0


def _paper_start(pb):
    nom = model.nominal_groups(pb.setup.config)
    st = {g: nom[g] for g in pb.free if g in nom}
    if "e0" in pb.free:
        st["e0"] = pb.e0_default()
    return st


def _side(tr, lo, hi, th, frac) -> str | None:
    """'lower' or 'upper' if the transformed value th lies within frac of
    the transformed range [lo, hi] of that bound."""
    tlo, thi = (math.log(lo), math.log(hi)) if tr == "log" else (lo, hi)
    edge = frac * (thi - tlo)
    if th - tlo < edge:
        return "lower"
    if thi - th < edge:
        return "upper"
    return None


def _at_bounds(pb, fr) -> list[tuple[str, str, float]]:
    """(group, 'lower'/'upper', bound) of every free group at a bound."""
    out = []
    for (name, tr, lo, hi), th in zip(fit.specs(pb, fr.effects), fr.theta):
        if name not in model.GROUPS or name in ("K",) or tr == "wnu":
            continue
        side = _side(tr, lo, hi, th, BOUND_EDGE)
        if side:
            out.append((name, side, lo if side == "lower" else hi))
    return out


def moved_inside(name, side, bound, k):
    """A start k steps (x3 per step for log groups, 0.15 for orders) inside."""
    tr = model.GROUPS[name][0]
    sgn = 1 if side == "lower" else -1
    if tr == "log":
        return bound * 3.0 ** (sgn * k)
    return bound + sgn * 0.15 * k


def _bound_meaning(name, side, bound) -> str | None:
    """What a group at this bound means physically (None: nothing more)."""
    if name == "beta" and side == "upper":
        return "the relay diaphragm acts as an integer-order element (beta = 1)"
    if name == "q" and side == "lower":
        return "the feedback spring is linear (q = 0, as in the paper's Example 7)"
    if name in ("tau", "RC", "RCd") and side == "lower":
        return f"{name} is faster than the sampling can show ({model.fmt_value(name, bound)})"
    return None


def _bound_words(name, side, bound) -> str:
    return (_bound_meaning(name, side, bound)
            or f"{name} sits at its {side} bound {model.fmt_value(name, bound)}")


def unstick(pb, best, say, notes: list):
    """Restart groups found at a bound (on the exploration copy). A restart
    that finds a better interior optimum replaces the fit; a group whose
    restarts all cost the same (within VISIBLE noise variances) does not
    matter to this record and is left to the identifiability test; one that
    the data pull back to the bound is held there."""
    work = search.explorer(pb) or pb
    cur = dict(best.values)
    cur_fit = best
    cost = fit.start_cost(work, (), cur)
    changed = False
    tried = set()
    budget = search._budget(work, (), search.EXPLORE_ITER)
    for _ in range(6):
        edge = [x for x in _at_bounds(pb, cur_fit) if x[0] not in tried]
        if not edge:
            break
        name, side, bound = edge[0]
        tried.add(name)
        runs = []
        for k in (1, 2):
            st = dict(cur)
            st[name] = moved_inside(name, side, bound, k)
            runs.append(fit.lm_fit(work, (), st, 0, budget, f"unstick {name} {k}"))
        r = search.best(runs)
        sig2 = cost / max(work.n_counted, 1)
        if r.cost < cost - VISIBLE * sig2 and not any(e[0] == name for e in _at_bounds(work, r)):
            notes.append(f"The first baseline fit ended with {name} at its {side} bound; a "
                         f"restart with {name} moved inside found a better optimum "
                         f"({name} = {model.fmt_value(name, r.groups[name])}).")
            say(f"baseline: {name} was at its {side} bound; a restart moved it inside")
            cur, cost, cur_fit, changed = dict(r.values), r.cost, r, True
            tried.discard(name)
            continue
        if abs(r.cost - cost) <= VISIBLE * sig2:
            continue                      # insensitive: not a corner
        pb.fixed[name] = bound
        pb.free.remove(name)
        pb.at_bound[name] = side
        notes.append(f"{name} ends at its {side} bound whatever the start "
                     f"({_bound_words(name, side, bound)}): held there, so that it does not "
                     "blur the identification of the others.")
        say(f"baseline: {name} held at its {side} bound")
        r = fit.lm_fit(work, (), cur, 0, budget, "held at bound")
        cur, cost, cur_fit, changed = dict(r.values), r.cost, r, True
    if not changed:
        return best
    return search.refine(pb, (), [("unstuck", cur)], iters=2 * search.REFINE_ITER)


def _ci_text(name, val, se):
    tr = fit.transform_of(name)
    if not math.isfinite(se) or (tr == "log" and 1.96 * se > 50):
        return "unbounded"
    if tr == "log":
        return f"x/ {math.exp(1.96 * se):.3g}"
    return f"+- {1.96 * se:.3g}"


def _id_width(pb, name) -> float:
    """Half-width of the 95 % interval within which a parameter counts as
    identified: a factor 2 for positive groups, 0.15 for orders, a tenth of
    the input's span for the operating point e0."""
    if name == "e0":
        return 0.1 * pb.span_e
    return ID_LOG if fit.transform_of(name) == "log" else ID_LIN


def prune(pb, best, say, reasons: dict):
    """Hold groups the record does not determine, worst first."""
    nom = model.nominal_groups(pb.setup.config)
    while True:
        nm = noise.fit(pb.fit_pieces(best.residual(pb)))
        # The AR model alone, not the ARFIMA one: the baseline's residual
        # holds every effect not yet modelled, whose slow part reads as long
        # memory, and the wider se then held groups a right model determines
        # (the time bench's id@1k record: q held as entangled, the lag then
        # found at 0.0058 s for 0.012). The extended models, whose intervals
        # are reported for the effects, keep it (fit.uncertainty's default).
        fit.uncertainty(pb, best, noise_model=noise.fit)
        sp = fit.full_specs(pb, best)
        worst, worst_ratio = None, 1.0
        for name, tr, _, _ in sp:
            if (name not in model.GROUPS and name != "e0") or name == "K":
                continue
            s = best.se.get(name, math.inf)
            ratio = 1.96 * s / _id_width(pb, name)
            if ratio > worst_ratio:
                worst, worst_ratio = name, ratio
        if worst is None:
            return best, nm
        names = [s[0] for s in sp]
        i = names.index(worst)
        col = best.jac[:, i] * _id_width(pb, worst)
        visible = float(col @ col) > VISIBLE * nm.var
        val = best.values.get(worst, best.groups.get(worst))
        # Entangled: the record determines a combination of it and others;
        # held where the fit put it, the fit stays at its optimum. Without a
        # visible effect it does not matter where it is held: the paper's
        # value (or the input's opening level for e0).
        if visible:
            held = val
        else:
            held = pb.e0_default() if worst == "e0" else nom[worst]
        held = keep_order(pb.setup.config, worst, held, best.groups)
        pb.fixed[worst] = held
        pb.free.remove(worst)
        why = "entangled with other groups" if visible else "no visible effect on this record"
        if visible:
            pb.entangled.append(worst)
        fmt = (lambda x: f"{x:.4g}") if worst == "e0" else (lambda x: model.fmt_value(worst, x))
        where = ("held at its fitted value " if visible else
                 "held at the input's opening level " if worst == "e0" else
                 "held at the paper's value ") + fmt(held)
        reasons[worst] = (
            f"not identified ({why}; 95 % interval {_ci_text(worst, val, best.se[worst])}): "
            + where + ("; freed again in the extended fits" if visible else ""))
        say(f"baseline: {worst} not identified ({why}); held")
        st = dict(best.values)
        st[worst] = held
        best = search.refine(pb, (), [("pruned", st)])


def keep_order(config: str, name: str, value: float, groups: dict) -> float:
    """A value to hold `name` at that the library accepts beside the other
    groups: pid needs nu <= w (nu held at its bound of 1, say, leaves the
    paper's w = 0.94 no room below it)."""
    if config != "pid" or name not in ("nu", "w"):
        return value
    other = groups.get("w" if name == "nu" else "nu")
    if other is None:
        return value
    return min(value, other) if name == "nu" else max(value, other)


# The label of the start at the paper's values (here and candidates._starts;
# candidates._apart explores it on its own where the model sits in a corner).
PAPER = "paper"


def starts(pb, rng, label=""):
    """The paper's values and the best fresh starts of the linear model."""
    fresh = search.rank_fresh(pb, (), fit.random_starts(pb, rng, N_FRESH), N_FRESH_KEEP)
    return [(PAPER, _paper_start(pb))] + [(f"fresh{i}", s) for i, s in enumerate(fresh)]


def premise_ratio(pb, fr) -> float:
    """The whitened residual's variance over the measured noise model's
    innovation variance (about 1 when the residual is that noise)."""
    n = max(pb.fit_white(pb.y).size, 1)
    return fr.cost / n / max(pb.nm.sigma2, 1e-300)


def _multistart(pb, rng, extra=()):
    return search.explore_refine(pb, (), starts(pb, rng) + list(extra),
                                 refine_iter=2 * search.REFINE_ITER, stage_iter=STAGE_ITER)


def weigh_or_not(pb, best, rng, say, notes: list):
    """Prewhitening by the noise measured at rest is the output's likelihood
    only if the model is right: then the whitened residual is that noise's
    innovation. The model's own error (a discretisation, inputs changing
    between samples, an effect the linear model lacks) is not noise, and a
    noise model whose innovations are far smaller than its sd (a resonant
    or slowly wandering sensor noise) amplifies the fast part of that error
    many times while slow errors cost almost nothing: the fit then trades
    gain and slow dynamics for the input's fast edges and lands in a corner
    (a clean dd PRBS record under AR(2) noise: held-out NRMSE 0.68 against a
    floor of 0.01). When the whitened residual of the best weighted fit is
    more than PREMISE x the innovation variance, the noise model does not
    describe the residual: the weighting is dropped, the baseline searched
    again as plain output error (consistent whatever the noise's colour),
    and every comparison whitens with the residual of the model with the
    effect, as for a record without a rest stretch."""
    if pb.nm is None:
        return best
    ratio = premise_ratio(pb, best)
    if ratio <= PREMISE:
        return best
    nm = pb.nm
    pb.nm = None
    say(f"baseline: the residual is {ratio:.3g}x the measured noise's innovation variance; "
        "refitted as plain output error")
    notes.append(f"The noise measured at rest ({nm.describe()}) does not describe the "
                 f"baseline's residual: whitened by it, the residual's variance is {ratio:.3g}x "
                 "the noise's innovation variance, so the model's own error, not the noise, "
                 "fills the criterion, and weighting by that noise model would trade the slow "
                 "response for the fast edges. The fits are plain output error instead, and "
                 "each effect is judged in that criterion: the drop in the plain cost over "
                 "the noise variance along the effect's contribution (the noise model of the "
                 "residual of the model with the effect) and the held-out error as measured.")
    return _multistart(pb, rng, [("weighted fit", dict(best.values))])


def at_edges(pb, vals: dict, effects=()) -> list[tuple[str, str, str, float, float]]:
    """(group, transform, 'lower'/'upper', lo, hi) of every group free in pb
    (K aside: it scales, it has no corner) that vals put within REPORT_EDGE
    of a bound of its range: the groups the report calls "at its bound", and
    the corners the extended fits also start away from
    (candidates.corner_freed). vals: the fit's values, with the groups pb
    frees and the fit held (held at a bound by unstick: at that bound). lo
    and hi are the group's own range (pid's w: from nu to 1; the search
    moves it as a fraction of that)."""
    out = []
    sp = fit.specs(pb, effects)
    for (name, tr, lo, hi), t in zip(sp, fit.to_theta(sp, vals, pb)):
        if name not in model.GROUPS or name == "K":
            continue
        side = _side(tr if tr == "log" else "lin", lo, hi, t, REPORT_EDGE)
        if side is None:
            continue
        if tr == "wnu":
            lo, hi = fit._nu(pb, vals), 1.0
        out.append((name, tr, side, lo, hi))
    return out


def corners(pb, fr) -> dict:
    """group -> what the report says of every group that the baseline fit
    `fr` leaves free within REPORT_EDGE of a bound (issue 8: such a group
    was reported identified with an interval across its bound). Only what
    is reported changes, never the fit. The interval is one-sided: from the
    bound to the far end of the sandwich interval (None: the record does not
    bound it). `determined`: that far end lies within the identification
    width of the bound, so the record puts the group at the bound (or the
    model wants it beyond the range); otherwise it is a corner the record
    does not determine."""
    out = {}
    for name, tr, side, lo, hi in at_edges(pb, fr.values, fr.effects):
        bound = lo if side == "lower" else hi
        far = fr.ci.get(name, (None, None))[1 if side == "lower" else 0]
        far = None if far is None else float(min(max(far, lo), hi))
        log = fit.transform_of(name) == "log"
        dist = (math.inf if far is None else
                abs(math.log(far / bound)) if log else abs(far - bound))
        determined = dist <= 2 * _id_width(pb, name)
        rel = ">=" if side == "upper" else "<="
        one = ("no 95 % interval inside the range" if far is None else
               f"one-sided 95 % interval {name} {rel} {model.fmt_value(name, far)}")
        why = ("the record puts it there: the model may want it beyond the range"
               if determined else "a corner: the record does not determine it")
        out[name] = {
            "side": side, "bound": float(bound), "value": float(fr.groups[name]),
            "interval95": [float(bound), far] if side == "lower" else [far, float(bound)],
            "determined": bool(determined),
            "words": (f"at its {side} bound {model.fmt_value(name, bound)}, not identified "
                      f"({'; '.join(filter(None, (why, one, _bound_meaning(name, side, bound))))})"),
        }
    return out


def report_corners(pb, fr, identified: dict) -> tuple[dict, dict]:
    """(identified without the groups at a bound, corners(pb, fr))."""
    c = corners(pb, fr)
    return {g: bool(v) and g not in c for g, v in identified.items()}, c


def fit_baseline(pb, rng, say):
    """(fit, identified, reasons, notes, noise model) of the linear model."""
    say(f"baseline: {len(pb.free)} parameters free ({', '.join(pb.free)}), multi-start")
    notes: list[str] = []
    best = _multistart(pb, rng)
    best = weigh_or_not(pb, best, rng, say, notes)
    reasons = {g: "fixed by --fix" for g in pb.user_fixed}
    best = unstick(pb, best, say, notes)
    for g, side in pb.at_bound.items():
        reasons[g] = f"held at its {side} bound ({_bound_words(g, side, pb.fixed[g])})"
    best, nm = prune(pb, best, say, reasons)
    identified = {g: g in pb.free for g in model.CONFIG_GROUPS[pb.setup.config]}
    return best, identified, reasons, notes, nm
