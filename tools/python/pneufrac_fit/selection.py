# SPDX-License-Identifier: MIT
"""Forward selection of effects, then a backward check.

Round 1 tests every catalogued effect on top of the baseline; the passing
effect with the lowest held-out NRMSE is added. Each later round tests the
remaining effects on top of the model chosen so far, until none passes.
Finally every chosen effect is tested again in the presence of all the
others (the model against the same model without it, same freedoms): one
that no longer passes is dropped, and the check repeated. So every effect
named passes the guards with the others in the model.

Groups the baseline held because they were entangled with others or sat at
a bound are freed again in every extended fit (the effect may be what
entangled them or pushed them there), and in its reference (the same model
without the effect) too.
"""
from __future__ import annotations

import os
import time

import numpy as np

from . import baseline, candidates, fit, guards, model, search, signals


def reference(pb, effects, fr, prior):
    """The model `effects` refitted with pb's freedoms, from the extended
    fit's optimum (its other values) and from the prior fit of `effects`."""
    effects = model.canonical(effects)
    dead = fr.dead if "dead_time" in effects else 0
    a = dict(fr.values)
    b = {**prior.groups, **prior.values}
    if "saturation" in effects and "K" not in b:
        b["K"] = fr.values["K"]
    return search.refine(pb, effects, [("from extended", a), ("prior", b)], dead=dead)


def play_start_unknown(pb):
    """A play (dead band) at rest sits at one of its edges, the one the last
    move before the record left it at; the model starts it centred. Both are
    at the same edge once the input has turned back for the first time, so
    with backlash in a comparison neither model counts the samples before
    the input's first reversal (and 2 % of the fit part more, for the
    difference to die away): the same samples for both."""
    import copy
    k = signals.first_reversal(pb.e_abs[:pb.nfit]) + int(fit.BURN * pb.nfit)
    if k <= pb.burn:
        return pb
    q = copy.copy(pb)
    q.burn = int(min(k, pb.nfit // 2))
    return q


def try_effect(pb, current, effect: str, seed: int, hint: dict | None = None):
    """Fit current + effect, its reference, and the guards. Groups the
    baseline held because they were entangled with others, or because they
    sat at a bound, are freed again (the missing effect may be what
    entangled them or pushed them there); the reference gets the same
    freedoms."""
    t0 = time.monotonic()
    rng = np.random.default_rng(seed)
    ent = [g for g in list(pb.entangled) + list(pb.at_bound)
           if g not in pb.user_fixed and g in pb.fixed]
    pbx = candidates.with_freed(pb, ent) if ent else pb
    if effect == "backlash":
        pbx = play_start_unknown(pbx)
    fr = candidates.fit_extended(pbx, current, effect, rng, hint)
    if fr.cost < fit.start_cost(pbx, current.effects, {**current.groups, **current.values},
                                current.dead) * (1 - 1e-6):
        ref = reference(pbx, current.effects, fr, current)
    else:       # no better than the model without it: no reference needed
        ref = current
    fit.uncertainty(pbx, fr)
    t = guards.test(pbx, effect, fr, ref, pb if ref is current else pbx)
    if t.passes:
        t = confirm(pbx, effect, fr, t, current, rng)
    t.pb = pbx
    t.elapsed = time.monotonic() - t0
    return t


def confirm(pb, effect, fr, t, current, rng):
    """Before an effect passes, its reference gets the baseline's whole
    search (the paper's values, fresh starts, the extended fit's groups,
    successive halving, a longer refinement): a gain that a better optimum
    of the model without the effect removes is no gain."""
    effects = model.canonical(current.effects)
    st = confirm_starts(fr, t.ref, current)
    if not effects:
        st += baseline.starts(pb, rng)
    dead = fr.dead if "dead_time" in effects else 0
    ref2 = search.explore_refine(pb, effects, st, dead=dead,
                                 refine_iter=2 * search.REFINE_ITER,
                                 stage_iter=baseline.STAGE_ITER)
    if ref2.cost >= t.ref.cost:
        return t
    t2 = guards.test(pb, effect, fr, ref2)
    t2.pb = pb
    return t2


def confirm_starts(fr, ref, current) -> list[tuple[str, dict]]:
    """The extended fit, the model so far and the reference as starts of the
    reference's whole search. The reference may be the model so far, fitted
    before the groups this test frees were free: each start's groups fill
    what its values lack (a start must name every free parameter)."""
    return [("from extended", {**fr.groups, **fr.values}),
            ("prior", {**current.groups, **current.values}),
            ("reference", {**ref.groups, **ref.values})]


def _run(args):
    return try_effect(*args)


def _hint(t) -> dict:
    """An effect's own parameters as fitted in a test, to start the next
    round from; nothing if the effect came to nothing there (its size is
    then no better a start than the catalogue's)."""
    if t is None or not t.peak >= guards.MATERIAL_SIGMAS:
        return {}
    names = {"lag": ["lag"], "saturation": ["sat_lo", "sat_hi"], "backlash": ["deadband"],
             "nozzle": ["nozzle_k", "nozzle_bias"], "dead_time": []}[t.effect]
    h = {k: t.model.values[k] for k in names if k in t.model.values}
    if t.effect == "dead_time":
        h["dead"] = t.model.dead
    return h


def run_round(pb, current, effects, seed, jobs, say, previous=None):
    prev = {t.effect: t for t in (previous or [])}
    tasks = [(pb, current, e, seed + 101 * (model.CAUSES.index(e) + 1), _hint(prev.get(e)))
             for e in effects]
    out = {}
    if jobs > 1 and len(tasks) > 1:
        import multiprocessing as mp
        try:
            ctx = mp.get_context("fork")
        except ValueError:
            ctx = None
        if ctx is not None:
            # the costliest tests first, and each worker with the parent's
            # threads: the last test running alone still uses every core
            threads = fit._threads
            with ctx.Pool(min(jobs, len(tasks)), initializer=fit.set_threads,
                          initargs=(threads,)) as pool:
                for t in pool.imap_unordered(_run, candidates.by_cost(tasks)):
                    _say(say, t)
                    out[t.effect] = t
            fit.set_threads(threads)
            return [out[e] for e in effects]
    for task in tasks:
        t = _run(task)
        _say(say, t)
        out[t.effect] = t
    return [out[e] for e in effects]


def _say(say, t):
    say(f"  + {t.effect}: val NRMSE {t.model.nrmse_val:.4f} (without {t.ref.nrmse_val:.4f}), "
        f"dBIC {t.dbic:+.1f}, peak {t.peak:.2g} sd -> "
        + ("passes" if t.passes else "fails: " + "; ".join(t.reasons[:2]))
        + f" ({t.elapsed:.1f} s)")


def forward(pb, base, seed, jobs, say, notes=None):
    """(final model, its problem, rounds of tests, backward tests). Sentences
    on effects left unnamed because the record cannot tell them apart go to
    `notes`."""
    current, cur_pb = base, pb
    rounds = []
    rivals, before = [], None
    while True:
        remaining = [c for c in model.CAUSES if c not in current.effects]
        if not remaining:
            break
        say(f"round {len(rounds) + 1}: effects on top of {current.effect}")
        tests = run_round(cur_pb, current, remaining, seed + 7 * len(rounds), jobs, say,
                          rounds[-1] if rounds else None)
        rounds.append(tests)
        lost = [t for t in tests if t.effect in rivals and not t.passes]
        if lost:
            current, cur_pb = _ambiguous(rounds[-2], current, lost, before, say, notes)
            break
        ok = [t for t in tests if t.passes]
        if not ok:
            break
        win = min(ok, key=lambda t: t.model.nrmse_val)
        rivals = [t.effect for t in ok if t is not win and guards.indistinguishable(win, t)]
        before = (current, cur_pb)
        say(f"round {len(rounds)}: {win.effect} added"
            + (f" (held-out error no better than {', '.join(rivals)}'s: each is tested on "
               "top of it next)" if rivals else ""))
        current, cur_pb = win.model, win.pb
    if len(current.effects) >= 2:
        current, cur_pb, checks = backward(cur_pb, current, say)
    else:   # a single effect was tested with everything else it could meet
        checks = [t for r in rounds for t in r if t.passes and t.model is current]
    return current, cur_pb, rounds, checks


def _ambiguous(tests, added, lost, before, say, notes):
    """The effect just added predicted the held-out part no better than a
    rival that adds nothing on top of it: both explain the same feature of
    the record, and the record does not say which is there. Naming either
    could send someone to take a healthy part apart, so neither is named:
    the model goes back to the one before."""
    win = next(t for t in tests if t.model is added)
    names = ", ".join(t.effect for t in lost)
    line = (f"{win.effect} and {names} explain the same feature of the record equally well "
            f"(held-out NRMSE {win.model.nrmse_val:.4f} against "
            + ", ".join(f"{t.effect}'s {r.model.nrmse_val:.4f}"
                        for t in lost for r in tests if r.effect == t.effect)
            + f"; {names} adds nothing on top of {win.effect}): the record cannot tell them "
            "apart, so neither is named.")
    say("ambiguous: " + line)
    if notes is not None:
        notes.append(line)
    return before


def backward(pb, fr, say):
    """Test every chosen effect against the model without it; drop the one
    that fails most clearly and repeat. Returns (model, problem, tests)."""
    while len(fr.effects) >= 2:
        tests = []
        for e in fr.effects:
            rest = tuple(x for x in fr.effects if x != e)
            prior = fr
            ref = reference(pb, rest, fr, prior)
            t = guards.test(pb, e, fr, ref)
            t.pb = pb
            tests.append(t)
        bad = [t for t in tests if not t.passes]
        if not bad:
            return fr, pb, tests
        worst = max(bad, key=lambda t: t.dbic)
        say(f"backward check: {worst.effect} no longer passes with the others "
            f"({'; '.join(worst.reasons[:2])}): dropped")
        fr = worst.ref
    # one effect left: its test is the one against the linear model
    ref = reference(pb, (), fr, fr)
    t = guards.test(pb, fr.effects[0], fr, ref)
    t.pb = pb
    if t.passes:
        return fr, pb, [t]
    say(f"backward check: {fr.effects[0]} no longer passes alone: dropped")
    return ref, pb, []
