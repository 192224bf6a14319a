# SPDX-License-Identifier: MIT
"""How effects are chosen (docs/analysis.md, "How effects are chosen").

Three mechanisms, each used everywhere it applies:

1. One test of an effect (try_effect, guards.test): the model with it
   against the same model without it, same freedoms (problem_for frees the
   groups the baseline held; reference and confirm refit the model without
   it) and same samples (play_start_unknown).
2. One comparison of two explanations (guards.distinguishable): the
   round's winner is named only if the record rejects every rival
   explanation of the same residual and not the winner, or rejects both
   and the winner explains the whole record significantly better, and
   never when the whole record significantly prefers the rival
   (rivals_of);
   a rival that adds nothing on top of it leaves neither named
   (_ambiguous).
3. One search order (forward): rounds of single effects, a round's winner
   added only if it predicts better than every model without it the round
   found, fitted on the same samples (models_without, winner_on), after
   the round's effects were refitted from a better optimum of the model so
   far that the round found, their references searched from it too
   (from_better), the winner refined from its own
   optimum (refine_winner), and every explanation of the round refitted
   from the winner's optimum (refit_rivals), whatever winner the round
   ends with refined as the first was (refine_final); pairs when a round
   adds nothing and the model is inadequate (pairs); a backward check of
   every named effect against the final model without it (backward), and
   rounds again on top of the model it leaves when it drops one. The
   baseline is the best linear fit on its own samples (best_same_fit).
"""
from __future__ import annotations

import contextlib
import copy
import itertools
import math
import time

import numpy as np

from . import baseline, candidates, fit, guards, lib, model, search, signals


def reference(pb, effects, fr, prior, better=None):
    """The model `effects` refitted with pb's freedoms, from the extended
    fit's optimum (its other values), from the prior fit of `effects`, and
    from `better` (a better optimum of the model so far that the round
    found: from_better)."""
    effects = model.canonical(effects)
    dead = fr.dead if "dead_time" in effects else 0

    def start_of(p):
        b = {**p.groups, **p.values}
        if "saturation" in effects and "K" not in b:
            b["K"] = fr.values["K"]
        return b

    fits = [search.refine(pb, effects, [("from extended", dict(fr.values)),
                                        ("prior", start_of(prior))], dead=dead)]
    if better is not None:
        # search.refine goes on from its best start only: the better model
        # so far is refined apart, not put in competition by start cost, so
        # that a start of the others that reaches a deeper optimum is still
        # refined (a reference left above where it was would favour the
        # effect). At its own delay (at the extended fit's, its shape is not
        # the better optimum, and the delay's profile can stick at a local
        # delay on the way back) and at the extended fit's: a start added,
        # none replaced
        for d in sorted({dead, better.dead if dead else 0}):
            fits.append(search.refine(pb, effects, [("better prior", start_of(better))],
                                      dead=d))
    # the delay free as in the extended fit (candidates.fit_extended); each
    # fit profiled before the lower is kept: adding a start can then only
    # lower the reference (a minimum taken before profiling need not be
    # the lower after it)
    return min((candidates.profile_dead(pb, effects, f) if dead else f for f in fits),
               key=lambda f: f.cost)


def play_start_unknown(pb):
    """A play (dead band) at rest sits at one of its edges, the one the last
    move before the record left it at; the model starts it centred. Both are
    at the same edge once the input has turned back for the first time, so
    with backlash in a comparison neither model counts the samples before
    the input's first reversal (and 2 % of the fit part more, for the
    difference to die away): the same samples for both. From there on the
    play's output still differs from the record's by a half-width (each is
    measured from its own rest): a constant step at the flapper, which the
    fitted output offset takes where no limit acts, but which saturation's
    limits, acting before that offset, must be moved by too (its step at
    the relay's output; analysis-bench.md, branch twofx4)."""
    k = signals.first_reversal(pb.e_abs[:pb.nsim]) + int(fit.BURN * pb.split.n_fit)
    if k <= pb.burn:
        return pb
    q = copy.copy(pb)
    q.burn = int(min(k, pb.split.first_end // 2))
    return q


def problem_for(pb, new_effects):
    """The problem on which effects are tested: groups the baseline held
    because they were entangled with others, or because they sat at a
    bound, freed again (the missing effect may be what entangled them or
    pushed them there); with backlash, the samples before the input's first
    reversal not counted (play_start_unknown)."""
    ent = [g for g in list(pb.entangled) + list(pb.at_bound)
           if g not in pb.user_fixed and g in pb.fixed]
    pbx = candidates.with_freed(pb, ent) if ent else pb
    if "backlash" in new_effects:
        pbx = play_start_unknown(pbx)
    return pbx


def _problem_of(pb, current, effect: str):
    """The problem a test of current + effect fits: saturation where the
    model so far has it, the effect's own options."""
    return problem_for(candidates.for_model(pb, current), (effect,))


def try_effect(pb, current, effect: str, seed: int, hint: dict | None = None, fitted=None,
               better=None):
    """Fit current + effect, its reference, and the guards. Groups the
    baseline held because they were entangled with others, or because they
    sat at a bound, are freed again (the missing effect may be what
    entangled them or pushed them there); the reference gets the same
    freedoms. fitted: this effect's fit, when a round already made it (from
    its own starts, or from a rival's optimum: rival_fit). A fit the
    library refuses on the way (a parameter set it cannot design, reached
    by a search step or a start) fails this test, with that reason; it
    does not end the diagnosis. better: a better optimum of the model so
    far than `current` (from_better): the reference and its confirmation
    are searched from it too, as the effect's fit was."""
    t0 = time.monotonic()
    try:
        return _try_effect(pb, current, effect, seed, hint, fitted, t0, better)
    except lib.ModelError as ex:
        t = guards.Test(effect, current, current)
        t.reasons.append(f"the library refused a fit of it ({ex})")
        t.pb = _problem_of(pb, current, effect)
        t.elapsed = time.monotonic() - t0
        return t


def _try_effect(pb, current, effect, seed, hint, fitted, t0, better=None):
    rng = np.random.default_rng(seed)
    pbx = _problem_of(pb, current, effect)
    pb = candidates.for_model(pb, current)   # the reference's problem, for the guards
    fr = fitted if fitted is not None else candidates.fit_extended(pbx, current, effect, rng,
                                                                    hint)
    pbx = candidates.for_model(pbx, fr)      # saturation where the fit placed it
    if search.lower(fr.cost, fit.start_cost(pbx, current.effects,
                                             {**current.groups, **current.values}, current.dead)):
        ref = reference(pbx, current.effects, fr, current, better)
    else:       # no better than the model without it: no reference needed
        ref = current
    fit.uncertainty_later(pbx, fr)     # made for the final model alone (diagnose)
    t = guards.test(pbx, effect, fr, ref, pb if ref is current else pbx, current)
    if t.passes:
        t = confirm(pbx, effect, fr, t, current, rng, better)
    t.pb = pbx
    t.better = better
    t.elapsed = time.monotonic() - t0
    return t


def rival_fit(t, current, rival):
    """from_rival for test t, on the problem its test fitted (t.pb:
    _try_effect's, saturation where its fit placed it)."""
    return from_rival(t.pb, current, t.effect, t.model, rival)


def from_rival(pb, current, effect, fr, rival):
    """current + effect refitted from the rival explanation's optimum: the
    rival test's groups and the parameters the two models share, with this
    effect's own size as this test fitted it (fr) and a dead time placed
    where the data put it on the rival's shape (candidates.scan_dead, then
    profiled). Explanations that imitate each other (a lag for a dead
    time, a nozzle's curvature for clipping) each pull the linear groups
    to the shape that suits them, and a fit started from the imitator's
    shape is the one the comparison of the two has to beat."""
    return from_model(pb, current, effect, fr, rival.model, set(OWN[rival.effect]),
                      "from " + rival.effect)


def from_model(pb, current, effect, fr, src, own, label):
    """current + effect refitted from another fit's optimum (src): refit_from
    on current's effects and this one."""
    return refit_from(pb, model.canonical(tuple(current.effects) + (effect,)), fr, src, own,
                      label)


def refit_from(pb, effects, fr, src, own, label):
    """fr (a fit of `effects`) refitted from another fit's optimum (src): its
    groups and the parameters it shares with fr, except `own` (src's own
    effects' parameters), with fr's own effects' sizes as fr has them; a
    dead time that src does not have placed where the data put it on src's
    shape (candidates.scan_dead, then profiled): a local refinement does
    not move a fitted delay, so started at fr's delay it would stay in the
    basin the refit is meant to leave."""
    effects = model.canonical(effects)
    st = {**fr.groups, **fr.values}
    st.update({k: v for k, v in {**src.groups, **src.values}.items()
               if k not in own and k in st})
    if "dead_time" in effects and "dead_time" not in src.effects:
        scan = candidates.scan_dead(pb, effects, st, candidates.dead_max(pb))
        d = next((dd for _, dd in scan if dd >= 1), fr.dead)
        r = search.refine(pb, effects, [(label, st)], dead=d)
        return candidates.profile_dead(pb, effects, r)
    dead = src.dead if "dead_time" in effects else 0
    r = search.refine(pb, effects, [(label, st)], dead=dead)
    return candidates.profile_dead(pb, effects, r) if dead else r


def confirm(pb, effect, fr, t, current, rng, better=None):
    """Before an effect passes, its reference gets the baseline's whole
    search (the paper's values, fresh starts, the extended fit's groups,
    successive halving, a longer refinement): a gain that a better optimum
    of the model without the effect removes is no gain. Where the model so
    far sits in a corner, the reference is also searched from that corner
    freed, as the extended fit was (candidates.explore_refine_corner), and
    from the paper's values, in every round: a gain that only leaving the
    corner brings is the reference's too."""
    effects = model.canonical(current.effects)
    st = confirm_starts(fr, t.ref, current)
    if better is not None:
        st.append(("better prior", {**better.groups, **better.values}))
    if not effects:
        st += baseline.starts(pb, rng)
    else:
        # from round 2 on, the paper shape keeping the model so far's
        # effects, as the extended fit has it (candidates._starts): beside a
        # corner it is explored on its own for both (candidates._apart), so
        # a gain that only this start brings is the reference's too
        st.append((baseline.PAPER, candidates._paper_shape(pb, {**current.groups,
                                                                **current.values})))
    dead = fr.dead if "dead_time" in effects else 0
    ref2 = candidates.explore_refine_corner(
        pb, effects, st, candidates.corner_start(pb, effects, current, {}), dead=dead,
        refine_iter=2 * search.REFINE_ITER, stage_iter=baseline.STAGE_ITER)
    if better is not None and dead and better.dead != dead:
        # the search above runs at one delay, the extended fit's; the better
        # model so far is an optimum at its own, and is refined there too
        # (reference() says why), the lower of the two kept. reference()
        # refined the same start on the same problem at that delay with
        # half the iterations: where that converged, this is its answer
        # (fit._answers: the whole-fit cache), no fit made; where it ran
        # out of iterations, this goes on further, not a repeat
        rb = search.refine(pb, effects, [("better prior", {**better.groups, **better.values})],
                           dead=better.dead, iters=2 * search.REFINE_ITER)
        ref2 = min(ref2, candidates.profile_dead(pb, effects, rb), key=lambda f: f.cost)
    if ref2.cost >= t.ref.cost:
        return t
    t2 = guards.test(pb, effect, fr, ref2, so_far=current)
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
    """One test of a round: (the test, whether its reference is the model
    so far: _as_made_here)."""
    t = try_effect(*args)
    return t, t.ref is args[1]


def _hint(t) -> dict:
    """An effect's own parameters as fitted in a test, to start the next
    round from; nothing if the effect came to nothing there (its size is
    then no better a start than the catalogue's)."""
    if t is None or not t.peak >= guards.MATERIAL_SIGMAS:
        return {}
    h = _own(t.model, t.effect)
    if "sat_lo" in h:
        # in the record's terms (the fit's limits are on its simulated
        # deviation, before its own offset): candidates.on_sim puts them on
        # the next fit's, whose offset is its model so far's
        c = candidates._sat_shift(t.pb, t.model)
        h = {**h, "sat_lo": h["sat_lo"] + c, "sat_hi": h["sat_hi"] + c}
    if t.effect == "dead_time":
        h["dead"] = t.model.dead
    return h


# Each effect's own fitted parameters (the search's names).
OWN = {"lag": ["lag"], "saturation": ["sat_lo", "sat_hi"], "backlash": ["deadband"],
       "nozzle": ["nozzle_k", "nozzle_bias"], "dead_time": []}


def _own(fr, effect) -> dict:
    return {k: fr.values[k] for k in OWN[effect] if k in fr.values}


def run_round(pb, current, effects, seed, jobs, say, previous=None):
    prev = {t.effect: t for t in (previous or [])}
    tasks = [(pb, current, e, _seed_of(seed, e), _hint(prev.get(e))) for e in effects]
    _corners_made(pb, current, effects)
    out = {}
    # the costliest tests first: the last test running alone is a short one
    with _workers(jobs, len(tasks)) as pool:
        if pool is None:
            done = map(_run, tasks)
        else:
            done = pool.imap_unordered(_run, candidates.by_cost(tasks))
        for t, same in done:
            t = _as_made_here(t, current, same)
            _say(say, t)
            out[t.effect] = t
    return [out[e] for e in effects]


def _seed_of(seed: int, effect: str) -> int:
    """The seed of an effect's test in a round seeded `seed` (its fresh
    starts): the same whether the test is made first or again."""
    return seed + 101 * (model.CAUSES.index(effect) + 1)


def _as_made_here(t, current, ref_is_current: bool):
    """t, made in a worker process, with its reference the model so far
    itself where it was that model there, not a pickled copy of it:
    models_without and best_same_fit tell the model so far from another
    fit of the same effects by identity."""
    if ref_is_current:
        t.ref = current
    return t


def _corners_made(pb, current, effects):
    """The model so far's corner freed (candidates.corner_freed) on every
    problem the round's tests fit, made here, before the round's workers
    fork: it depends on the problem and the model so far alone, and each
    test would otherwise make it again in its worker (with a dead band,
    which counts fewer samples, there are two problems)."""
    for e in effects:
        try:
            candidates.corner_freed(_problem_of(pb, current, e), current)
        except lib.ModelError:
            pass    # the test meets the refusal again and fails with it (try_effect)


@contextlib.contextmanager
def _workers(jobs: int, n: int):
    """A pool of min(jobs, n) forked worker processes for n independent
    fits, or None where this process does them (jobs 1, a single fit, no
    fork on this system). Each worker gets the parent's threads: the last
    fit running alone still uses every core. Forked, a worker inherits what
    the parent made before (_corners_made)."""
    if jobs <= 1 or n <= 1:
        yield None
        return
    import multiprocessing as mp
    try:
        ctx = mp.get_context("fork")
    except ValueError:
        yield None
        return
    threads = fit._threads
    try:
        with ctx.Pool(min(jobs, n), initializer=fit.set_threads, initargs=(threads,)) as pool:
            yield pool
    finally:    # the parent's threads again, also when a fit in the pool raised
        fit.set_threads(threads)


def _say(say, t):
    say(f"  + {t.effect}: val NRMSE {t.model.nrmse_val:.4f} (without {t.ref.nrmse_val:.4f}), "
        f"dBIC {t.dbic:+.1f}, peak {t.peak:.2g} sd -> "
        + ("passes" if t.passes else "fails: " + "; ".join(t.reasons[:2]))
        + f" ({t.elapsed:.1f} s)")


def forward(pb, base, seed, jobs, say, notes=None, sets=None, _tried=None):
    """(final model, its problem, rounds of tests, backward tests). Sentences
    on effects left unnamed because the record cannot tell them apart go to
    `notes`, and the sets of those effects to `sets`. When the backward
    check drops an effect, the model left was never tested for additions
    (the other effects were tried on top of the model with the dropped one):
    the rounds go on from it (stepwise selection, forward again after a
    step back), each set of effects tried on once (_tried)."""
    current, cur_pb = base, pb
    rounds = []
    rivals, before = [], None
    last = None             # (the last round's winner, the model it was added on)
    tested_on = {}          # id(model) -> the round of tests on top of it
    tried = set() if _tried is None else _tried
    while True:
        remaining = [c for c in model.CAUSES if c not in current.effects]
        if not remaining or model.canonical(current.effects) in tried:
            break
        tried.add(model.canonical(current.effects))
        say(f"round {len(rounds) + 1}: effects on top of {current.effect}")
        tests = run_round(cur_pb, current, remaining, seed + 7 * len(rounds), jobs, say,
                          rounds[-1] if rounds else None)
        rounds.append(tests)
        tests = from_better(cur_pb, current, tests, seed + 7 * len(rounds) + 9, say)
        refined = []        # the tests refinement left (refine_final)
        tests = refine_final(cur_pb, current, tests, refined, seed + 7 * len(rounds) + 11,
                             say)
        rounds[-1] = tested_on[id(current)] = tests
        # a rival of the last winner that fails on top of it, judged on its
        # best fit: one that failed only because its search stopped short of
        # a better model so far (from_better) is not lost
        lost = [t for t in tests if t.effect in rivals and not t.passes]
        if lost:
            current, cur_pb = _ambiguous(rounds[-2], current, lost, before, say, notes,
                                         sets)
            break
        say_new = _once(say)    # _passing runs twice a round: its verdicts, said once
        if not _passing(tests, current, cur_pb, len(rounds), say_new):
            break
        tests = refit_rivals(cur_pb, current, tests, seed + 7 * len(rounds) + 5, say, jobs)
        tests = refine_final(cur_pb, current, tests, refined, seed + 7 * len(rounds) + 11,
                             say)
        rounds[-1] = tested_on[id(current)] = tests
        ok = _passing(tests, current, cur_pb, len(rounds), say_new)   # refits bring new references
        if not ok:
            break
        win = _winner(ok)
        rivals = rivals_of(win, tests)
        before = (current, cur_pb)
        say(f"round {len(rounds)}: {win.effect} added"
            + (f" (not significantly better than {', '.join(rivals)}: each is tested on "
               "top of it next)" if rivals else ""))
        last = (win, before)
        current, cur_pb = win.model, win.pb
    on_top = tested_on.get(id(current))
    got = None
    if on_top:
        got = pairs(cur_pb, current, on_top, say, notes, sets, seed + 7 * len(rounds))
        if got is not None:
            current, cur_pb, tests = got
            rounds.append(tests)
    # one effect standing in for two: a verdict of a single effect (added on
    # the baseline) whose model is still inadequate; a model that names two
    # already is not what the imitation leaves, and pairs cost about three
    # refinements each, so they are not tried in place of its last member
    if got is None and last is not None and last[0].model is current and not last[1][0].effects:
        got = pairs_instead(last, tested_on.get(id(last[1][0])), current, cur_pb, say, notes,
                            sets, seed + 7 * len(rounds) + 13)
        if got is not None:
            current, cur_pb, tests = got
            if tests:
                rounds.append(tests)
    if len(current.effects) >= 2:
        current, cur_pb, checks = backward(cur_pb, current, say)
        if model.canonical(current.effects) not in tried:
            say(f"after the backward check: rounds again, on top of {current.effect} (never "
                "tried); their progress marked 'again'")
            more = forward(cur_pb, current, seed + 7 * len(rounds) + 3, jobs,
                           lambda m: say("again: " + m), notes, sets, tried)
            # nothing added there: the backward check's tests stand
            return more[0], more[1], rounds + more[2], checks if more[0] is current else more[3]
    else:   # a single effect was tested with everything else it could meet
        checks = [t for r in rounds for t in r if t.passes and t.model is current]
    return current, cur_pb, rounds, checks


# A fit of the same effects replaces the one kept only when its BIC is lower
# by more than this: under 2 the difference is "not worth more than a bare
# mention" (Kass and Raftery 1995), and refits that end a rounding error
# apart would otherwise churn the model kept.
SAME_FIT_DBIC = 2.0


def _bic(pb, fr) -> float:
    """fr's BIC on pb's counted fit samples, whitened as pb's fits are (the
    fit criterion, with fr's own count of parameters); K, pc0 and the
    start's terms solved on those samples (fit.start_cost)."""
    pb = candidates.for_model(pb, fr)
    m = max(pb.n_counted, 1)
    c = fit.start_cost(pb, fr.effects, {**fr.groups, **fr.values}, fr.dead)
    return m * math.log(max(c, 1e-300) / m) + fr.k * math.log(m) if math.isfinite(c) else math.inf


def best_same_fit(tests, current, cur_pb):
    """(model, problem, source): the best fit of current's effects that a
    round found, on the fit criterion, and the test whose reference it
    came from (current, cur_pb, "" when none is better).

    Every test of a round refits the model so far as its reference, with
    the freedoms the test frees and, beside a dead band, without the
    samples before the input's first reversal; such a refit can end in a
    better optimum than the model so far. Which is better is decided on the
    fit part, never on the held-out part (it would then no longer be held
    out, and the reported held-out error would be chosen, not measured):
    by BIC (the whitened residual's likelihood less ln(m)/2 per parameter,
    as the guards count a model's freedoms), lower by more than
    SAME_FIT_DBIC, both models on the same
    samples: the model so far's (a reference fitted on fewer samples is
    refined on them first). A reference that beats the model so far only
    on the samples it was fitted to, or only held out, is not a better fit
    (analysis-bench.md, "The fit kept when a round names nothing"). The
    held-out part may only refuse a replacement, one that predicts it
    worse, as the guards refuse an effect that predicts worse than the
    model so far: the model kept has then passed the same held-out tests
    (on a blind pid record a refit 1643 BIC lower on the fit part
    predicted the held-out part at 0.176 against 0.098)."""
    same = model.canonical(current.effects)
    refs = [t for t in tests if t.ref is not current
            and model.canonical(t.ref.effects) == same]
    if not refs:
        return current, cur_pb, ""
    score = _bic(cur_pb, current)
    best = (current, cur_pb, "")
    for t in refs:
        p = on_samples(t.pb, t.ref, cur_pb.burn)   # the test's freedoms, the model so far's samples
        if not _bic(p, t.ref) < score - SAME_FIT_DBIC:
            continue
        r = search.refine(p, same, [("reference of " + t.effect,
                                     {**t.ref.groups, **t.ref.values})], dead=t.ref.dead)
        b = _bic(p, r)
        if b < score - SAME_FIT_DBIC and r.nrmse_val <= current.nrmse_val:
            score, best = b, (r, p, t.effect)
    return best


def _once(say):
    """say, silent on a line it has said already: a rival's verdict that
    the round's refits left unchanged is news only the first time."""
    said = set()

    def say_once(msg):
        if msg not in said:
            said.add(msg)
            say(msg)
    return say_once


def _passing(tests, current, cur_pb, n_round: int, say) -> list:
    """The round's tests that pass, or none when a model without a new
    effect (models_without) predicts the held-out part significantly
    better than the best of them fitted on the same samples (winner_on,
    _rival_z)."""
    ok = [t for t in tests if t.passes]
    if not ok:
        return []
    best = _winner(ok)
    for r, burn in models_without(tests, current, cur_pb):
        if r is not current and burn > cur_pb.burn and not r.nrmse_val < current.nrmse_val:
            # Fitted on fewer samples and predicting no better than the
            # model so far: the stretch it left out held nothing it could
            # not follow, so there is no advantage to take from the winner,
            # and the model so far (checked too) is the fairer rival.
            continue
        w = winner_on(best, burn)
        if not r.nrmse_val <= w.nrmse_val:
            continue
        fewer = " on the same samples" if w is not best.model else ""
        who = ("the model so far" if r is current else
               "the model without a new effect, refitted with another test's freedoms,")
        z = _rival_z(best, r, w)
        if not z > guards.Z95:
            # the NRMSEs keep each held-out block's level, the z (as the
            # guards) does not: the two can disagree in sign
            say(f"round {n_round}: {who} predicts the held-out part at NRMSE "
                f"{r.nrmse_val:.4f} against {best.effect}{fewer} {w.nrmse_val:.4f}, not "
                f"significantly better (each held-out block less its level: {z:.2f} sd, need "
                f"> {guards.Z95:.3g}): {best.effect} stands")
            continue
        say(f"round {n_round}: {who} predicts the held-out part significantly better than "
            f"{best.effect}{fewer} (NRMSE {r.nrmse_val:.4f} against {w.nrmse_val:.4f}, "
            f"{z:.2f} sd): no effect added")
        return []
    return ok


# When a model without the new effect beats the round's winner. The winner
# passed every guard against its own reference: a material and (where the
# fits were whitened) significant held-out gain, a likelihood ratio and a
# contribution well above the noise. A model without the effect found with
# other freedoms or on fewer samples (models_without) is a fair reason to
# drop it only when the record says that model predicts the held-out part
# better than the winner, on the same samples, by the held-out comparison's
# own test (guards._held_z: the improvement over the sd the winner's noise
# model gives it, whitened as the fits were), at the guards' level (Z95,
# one-sided 2.5 %). Why not the raw comparison of the two NRMSEs, as
# before: when the two models predict the held-out part equally well (the
# effect cannot be seen on the samples the rival was fitted to), which of
# the two comes out lower is decided by the held-out part's noise, about
# half the time each way, so an effect with every guard passed was dropped
# on a coin flip (the independent simulator's two-nozzle-lag seed 5: the
# lag model fitted without the opening stretch predicts at 0.0131, the lag
# + nozzle on the same samples at 0.0134, 1.58 sd; branch passing33). A
# tie is no evidence against the effect, and the evidence for it stands: a
# rival fitted on fewer samples ties only by leaving a stretch of the fit
# part unexplained, which the effect's model explains (its likelihood
# ratio, on every sample); one fitted with another test's freedoms on the
# same samples differs from the effect's own reference in little but its
# search's optimum (problem_for frees the same held groups for every
# test), and a better optimum is weighed by the fit criterion
# (from_better), not by the held-out part. A rival that predicts significantly better is evidence that
# the effect's fit, on the samples the rival kept, costs prediction, and
# the effect is refused (two-backlash-saturation seed 1: saturation 0.0783
# against the linear model's 0.0682 on the same samples, 4.09 sd; a true
# saturation whose advantage lies before the input's first reversal,
# lost as before: docs/analysis.md, Known limits).
def _rival_z(t, r, w) -> float:
    """How many sd (guards._held_z) model r, without t's effect, predicts the
    held-out part better than w (t's model on the samples r was fitted to),
    under t's noise model, whitened where t's fits were (where its test
    asked its held-out z: t.z_asked), each held-out block less its own mean
    as the guards take it. t.pb is the problem its test was made on."""
    pb = t.pb
    c_r = pb.split.centre_held(r.residual(pb))
    c_w = pb.split.centre_held(w.residual(pb))
    return guards._held_z(pb, t.nm, c_w, c_r, t.z_asked)


def winner_on(t, burn: int):
    """t's model fitted on the samples a model without it was fitted on:
    as it is when those are t's own or more (samples t's own test left
    out stay out), otherwise refined from its optimum without the samples
    before `burn` (a dead band's test fits its reference without the
    samples before the input's first reversal). Kept on t: a round asks
    for it more than once."""
    if burn <= t.pb.burn:
        return t.model
    done = getattr(t, "on_fewer", {})
    if burn not in done:
        p = on_samples(t.pb, t.model, burn)
        fr = search.refine(p, t.model.effects,
                           [("on fewer samples", {**t.model.groups, **t.model.values})],
                           dead=t.model.dead)
        # the delay free, as in every reference (reference(), above)
        done[burn] = (candidates.profile_dead(p, fr.effects, fr)
                      if "dead_time" in fr.effects else fr)
        t.on_fewer = done
    return done[burn]


def on_samples(pb, fr, burn: int):
    """pb (its freedoms) counting the samples from `burn` on, set up for
    fr's model (candidates.for_model): the problem on which a model is
    refitted to be compared with one fitted on those samples."""
    p = copy.copy(pb)
    p.burn = burn
    return candidates.for_model(p, fr)


def refit_rivals(pb, current, tests, seed, say, jobs: int = 1):
    """The round's tests, each explanation refitted from the winner's
    optimum (from_rival) before the winner is taken, and again from each
    new winner's, until the winner stays (each pair once). A round compares
    explanations by their fits, and each fit is the best optimum its own
    starts reached: an explanation fitted from a poorer start than its
    rival's loses to it for that reason alone (a dead time placed where the
    baseline's shape put it, 3 samples, against a lag that moved the shape
    to a 10-sample delay). The refit replaces a test only when it fits the
    fit part better (the fit criterion, never the held-out part); every
    guard is then applied to it as to any test. jobs: worker processes for
    a pass's refits."""
    tests = list(tests)
    done = set()
    while True:
        win = _winner(tests)
        if win is None:
            return tests
        todo = [i for i, t in enumerate(tests) if t is not win and explains(t)
                and (t.effect, win.effect) not in done]
        if not todo:
            return tests
        done.update((tests[i].effect, win.effect) for i in todo)
        # the pass's refits are independent (each from its own test and the
        # same winner): in the workers, taken back in the tests' order
        args = [(pb, current, tests[i], win, seed) for i in todo]
        with _workers(jobs, len(args)) as pool:
            got = list(map(_refit, args) if pool is None else pool.map(_refit, args, 1))
        for i, (t2, same) in zip(todo, got):
            if t2 is not None:  # else no better fit: the test stands, its guards need no rerun
                _say_again(say, tests[i], t2, f"refitted from the {win.effect} fit's optimum")
                tests[i] = _as_made_here(t2, current, same)


def _refit(args):
    """One refit of refit_rivals: (the test again on the refit, whether its
    reference is the model so far: _as_made_here), or (None, False) when
    the refit is no better than the test's own fit (_test_again)."""
    pb, current, t, win, seed = args
    t2 = _test_again(pb, current, t, rival_fit(t, current, win), seed)
    return t2, t2 is not None and t2.ref is current


def _test_again(pb, current, t, fr, seed, better=None):
    """t's effect tested again on fr, a fit of its model found after its
    test, when fr fits the fit part better (the fit criterion, never the
    held-out part), and still does after the test's own refinement; every
    guard is applied to it as to any test's fit (better: try_effect; by
    default the one t's reference was searched from, so that a later
    refinement of a test from_better made keeps its reference's start).
    None otherwise."""
    if not search.lower(fr.cost, t.model.cost):
        return None
    better = t.better if better is None else better
    t2 = try_effect(pb, current, t.effect, _seed_of(seed, t.effect), fitted=fr, better=better)
    if not search.lower(t2.model.cost, t.model.cost):
        return None
    _carry_refs(t2, t, t.ref, current)
    return t2


def _say_again(say, t, t2, why):
    say(f"  {t.effect} {why}: cost {t.model.cost:.6g} -> {t2.model.cost:.6g}, val NRMSE "
        f"{t.model.nrmse_val:.4f} -> {t2.model.nrmse_val:.4f} -> "
        + ("passes" if t2.passes else "fails: " + "; ".join(t2.reasons[:2])))


# Refining the round's winner from its own optimum: a few times the
# refinement that ended its search (search.REFINE_ITER), which the
# winner's search shares with every start it explored; the fit stops
# earlier where it converges (fit.lm_fit's ftol).
WINNER_ITER = 4 * search.REFINE_ITER


def _retested(pb, current, tests, i, fr, seed, say, why, better=None):
    """tests with tests[i] tested again on fr where it fits better
    (_test_again)."""
    t2 = _test_again(pb, current, tests[i], fr, seed, better)
    if t2 is None:
        return tests
    _say_again(say, tests[i], t2, why)
    tests = list(tests)
    tests[i] = t2
    return tests


def from_better(pb, current, tests, seed, say):
    """The round's tests, each effect that explains part of the residual
    (or passes) refitted from a better optimum of the model so far when
    the round found one (best_same_fit: a test's reference, or its
    confirmation search, better on the model so far's samples by the fit
    criterion). The model with an effect nests the model without it, so
    its search should start from the best model without it there is: an
    extended fit started from a poorer optimum of the model so far can end
    short of what the record has, and then lose to a model without the
    effect that was refitted better, for its search and not for the data.
    Once per round (the better model is the one best_same_fit found among
    this round's references); a refit replaces a test only when it fits
    its fit part better (_retested). A test whose own fit the refit does
    not improve is tested again on that fit, its reference searched from
    the better model too, when its reference fits the test's samples
    worse than the better model does (_referred_again): the reference must
    be at least as good a model without the effect as one already known."""
    todo = [i for i, t in enumerate(tests) if t.passes or explains(t)]
    if not todo:
        return tests
    better, _, src = best_same_fit(tests, current, pb)
    if better is current:
        return tests
    say(f"  the model so far ({current.effect}) refitted as the {src} test's reference fits "
        f"better on the same samples (cost {current.cost:.6g} -> {better.cost:.6g}): each "
        "effect that explains part of the residual is refitted from it")
    for i in todo:
        t = tests[i]
        # t.pb: the problem its test fitted (_try_effect), saturation where
        # its fit placed it
        fr = from_model(t.pb, current, t.effect, t.model, better, (),
                        f"from a better {current.effect} fit")
        # the effect's fit starts from the better model so far, and so does
        # its reference: a reference searched only from the poorer model so
        # far and the effect's fit can end short of the better one, and the
        # effect would be credited with what a better fit without it does
        tests = _retested(pb, current, tests, i, fr, seed, say,
                          f"refitted from the better {current.effect} fit", better)
        if tests[i] is t:
            # the effect's fit was at its optimum already, and so stays;
            # its reference may still have stopped short of the better
            # model so far, and then the guards would credit the effect
            # with what a model already known without it does
            tests = _referred_again(pb, current, tests, i, better, seed, say)
    return tests


def _earlier_refs(t) -> tuple:
    """The references t had before a retest replaced them
    (_referred_again, _test_again); a test built elsewhere than
    guards.test (the tests' stand-ins) may not carry the field: none."""
    return tuple(getattr(t, "also_without", ()))


def _carry_refs(keep, t, dropped, current=None) -> None:
    """keep's earlier references (also_without): t's, and `dropped`, the
    reference of the test that keep replaced or was kept over
    (_test_again, _referred_again). They are still models without the
    effect fitted on the test's samples: a retest adds to them and drops
    none, so that the models the winner must beat (models_without) can
    only grow. Not none, nor keep's own reference again, nor (any of
    them) `current` where given: _test_again runs in forked workers too (refit_rivals),
    where a test's reference can be the worker's unpickled copy of the
    model so far, which models_without, telling the model so far by
    identity, would list as a second one; _referred_again runs in the
    parent, where models_without drops the model so far itself."""
    again = dropped is None or dropped is keep.ref
    refs = [*_earlier_refs(t), *(() if again else (dropped,))]
    keep.also_without = [r for r in refs if current is None or r is not current]


def _cost_on(t, m) -> float:
    """m's cost (a fit without t's effect) on t's problem: its freedoms,
    samples and weighting, m's delay, K and pc0 re-solved, and m's
    saturation where m's fit placed it: m's values carry their own
    sat_kind, which decides the placement simulated; candidates.for_model
    (as _bic) only makes the problem agree with them, a price it does not
    change."""
    pb = candidates.for_model(t.pb, m)
    return fit.start_cost(pb, m.effects, {**m.groups, **m.values}, m.dead)


def _short_of(t, better) -> bool:
    """Whether t's reference fits the fit part worse than `better` (a fit of
    the same effects) does, both on t's problem (its freedoms and samples):
    the fit criterion, with _test_again's margin."""
    return search.lower(_cost_on(t, better), _cost_on(t, t.ref))


def _referred_again(pb, current, tests, i, better, seed, say):
    """tests with tests[i] tested again on its own fit, its reference
    searched from `better` too (try_effect), when its reference stopped
    short of `better` (_short_of); every guard again.

    One-way: the retest can only raise the bar, so that no effect passes
    that did not pass before. Only a passing test is retested (a failing
    one stays failed: several guards, the held-out gain and those on the
    difference of the two fits, do not get stricter as the reference's fit
    part cost falls, so a new reference could let a test pass that failed
    against the old one). The effect passes only if it passes both: a
    retest that fails replaces the test, whatever its reference; one that
    passes replaces it only if its reference fits t's samples better (the
    same problem, samples and weighting: _cost_on), its guards then
    against the stronger of the two. Whichever is kept carries the other's
    reference (also_without), so that both stay among the models without
    the effect that the winner must beat (models_without)."""
    t = tests[i]
    if not t.passes or not _short_of(t, better):
        return tests
    t2 = try_effect(pb, current, t.effect, _seed_of(seed, t.effect), fitted=t.model,
                    better=better)
    old, new, best = _cost_on(t, t.ref), _cost_on(t, t2.ref), _cost_on(t, better)
    raised = search.lower(new, old)
    say(f"  {t.effect} referred to the better {current.effect} fit (on its samples: "
        f"reference {old:.6g}, better {best:.6g}): reference {new:.6g} -> "
        + ("passes" if t2.passes else "fails: " + "; ".join(t2.reasons[:2])))
    if search.lower(best, new):
        say(f"  warning: {t.effect}'s reference is still short of the better "
            f"{current.effect} fit")
    keep, drop = (t2, t) if raised or not t2.passes else (t, t2)
    _carry_refs(keep, t, drop.ref)
    keep.better = better
    tests = list(tests)
    tests[i] = keep
    return tests


def refine_winner(pb, current, tests, seed, say):
    """The round's tests, with the winner (the passing test that predicts
    the held-out part best) refined further from its own optimum before it
    meets its rivals (the models without it, _passing; the other
    explanations, refit_rivals and guards.distinguishable). Every
    explanation is compared as its search left it, and a winner whose
    search stopped short of its optimum is refused for what the search
    missed, not for what the record says; the rivals get the winner's
    optimum (refit_rivals), the winner gets its own. Kept only when it
    fits the fit part better (_retested), then every guard again."""
    win = _winner(tests)
    if win is None:
        return tests
    i = next(j for j, t in enumerate(tests) if t is win)
    w = win.model
    p = candidates.for_model(win.pb, w)
    # the same start's fit, refined further: it keeps that start's label
    # (candidates.corner_notes tells where a named effect's fit came from)
    fr = search.refine(p, w.effects, [(w.start, {**w.groups, **w.values})],
                       dead=w.dead, iters=WINNER_ITER)
    if "dead_time" in w.effects:
        fr = candidates.profile_dead(p, fr.effects, fr)
    return _retested(pb, current, tests, i, fr, seed, say, "refined from its own optimum")


def _winner(tests):
    """The round's winner: the passing test that predicts the held-out part
    best (None when none passes)."""
    ok = [t for t in tests if t.passes]
    return min(ok, key=lambda t: t.model.nrmse_val) if ok else None


def refine_final(pb, current, tests, done, seed, say):
    """The round's tests, with the winner refined from its own optimum
    (refine_winner) until the winner is a test that refinement left.
    Refinement is what the winner meets its rivals with, so it follows
    the winner wherever the round moves it: a refined winner that now
    fails a guard hands the round to another passing test, and
    refit_rivals can promote a rival refitted from the winner's optimum;
    either would otherwise meet the models without it (_passing) and be
    added as its search left it. `done`: the tests refinement left this
    round (extended here), so that each is refined once; each pass
    replaces one test not in it with one in it, so the loop ends.
    Asymmetric: a winner that refit_rivals promoted is refined here, but
    no rival is refitted again from its refined optimum (refit_rivals is
    costly); the rivals it meets were refitted from the first winner's."""
    while True:
        w = _winner(tests)
        if w is None or any(w is d for d in done):
            return tests
        i = next(j for j, t in enumerate(tests) if t is w)
        tests = refine_winner(pb, current, tests, seed, say)
        done.append(tests[i])


def models_without(tests, current, cur_pb) -> list:
    """(model, the first sample its fit counted) for every model without a
    new effect that a round found: the model so far, and each test's
    reference (the same effects refitted with the freedoms and samples
    that test gave them; and the references it had before a retest:
    _referred_again, _test_again). An effect whose model predicts the
    held-out part no better than one of them explains nothing the model so
    far cannot,
    refitted: its gain over its own reference is then the freedoms', and
    naming it would credit an effect with what a better fit of the model
    without it does. Held-out errors compare models fairly whatever their
    freedoms, but not whatever their samples: a fit that leaves out a
    stretch of the record predicts the rest better when the stretch holds
    what the model cannot follow (the effect, or a disturbance), so the
    effect is compared with each such fit refitted on the same samples
    (winner_on)."""
    same = model.canonical(current.effects)
    out = [(current, cur_pb.burn)]
    out += [(m, t.pb.burn) for t in tests for m in (t.ref, *_earlier_refs(t))
            if model.canonical(m.effects) == same and m is not current]
    return out


def explains(t) -> bool:
    """Whether a tested effect explains part of the residual: significant
    against its reference on the fit part, and predicting the held-out part
    better than its reference (one that predicts worse explains nothing),
    as measured and in the fits' own criterion (guards._held_z; nan: not
    measured)."""
    return bool(t.excludes and t.val_gain > 0 and not t.val_z <= 0)


def half_story(t) -> bool:
    """Whether a tested effect may be one member of a pair: significant
    against its reference on the fit part. Not also predicting the
    held-out part better (`explains`): fitted alone, a member also bends
    its own and the freed groups' parameters to imitate the missing other
    member, and that imitation is what can predict worse held-out; the
    pair's members meet every guard, the held-out one included, when the
    pair is tested."""
    return bool(t.excludes)


def pairs(pb, current, tests, say, notes=None, sets=None, seed=0, tied=None):
    """Two effects at once, when forward selection added nothing more but
    the model is inadequate (guards.inadequate: its whitened residual still
    depends on the input). One at a time cannot find two effects neither of
    which passes alone (each is only half the story, and the other half
    counts against it). Every pair of effects that are significant on
    their own (`half_story`) is fitted on top of the model, as each
    member's model extended by the other (candidates.fit_extended, the
    better of the two orders); each member
    is then tested with every guard against the pair without it (the other
    member's model refitted with the same freedoms). The pair whose members
    both pass and that predicts the held-out part best is added, if the
    record tells it from every other such pair (guards.distinguishable);
    otherwise none is, and the pairs the record cannot tell apart are
    appended to `tied` (a list, when given: each pair's members' tests).
    Returns (model, problem, the members' tests) or None."""
    expl = [t for t in tests if half_story(t)]
    if len(expl) < 2:
        return None
    bad, z = guards.inadequate(pb, current)
    if not bad:
        return None
    say(f"pairs: {current.effect} is inadequate (its whitened residual correlates with the "
        f"input at {z:.1f} sd); testing pairs of " + ", ".join(t.effect for t in expl))
    found = []
    rng = np.random.default_rng(seed)
    for a, b in itertools.combinations(expl, 2):
        t0 = time.monotonic()
        placed = next((t.model for t in (a, b) if t.effect == "saturation"), current)
        pbx = problem_for(candidates.for_model(pb, placed), (a.effect, b.effect))
        # each member's model extended by the other, as a round extends the
        # model so far (warm and fresh starts, the other's own fitted size,
        # a dead time profiled): a local refinement from the two members'
        # parameters merged does not move a fitted delay, and from a
        # member that was imitating the other it stays where the
        # imitation put it
        fr = search.best([candidates.fit_extended(pbx, x.model, y.effect, rng, _hint(y))
                          for x, y in ((a, b), (b, a))])
        members = _members(pbx, fr, current, ((a, b.model), (b, a.model)))
        ok = _admitted(members, named=True)
        say(f"  + {a.effect}+{b.effect}: val NRMSE {fr.nrmse_val:.4f} -> "
            + ("both pass" if ok else "; ".join(f"{t.effect} fails: {t.reasons[0]}"
                                                 for t in members if not t.passes))
            + f" ({time.monotonic() - t0:.1f} s)")
        found.append((members, ok))
    good = [m for m, ok in found if ok]
    if not good:
        return None
    win = min(good, key=lambda m: m[0].model.nrmse_val)
    rivals = [m for m, _ in found if m is not win and _admitted(m, named=False)
              and not guards.distinguishable(win[0], m[0])]
    if rivals:
        both = [win] + rivals
        _cannot_tell(["+".join(t.effect for t in m) for m in both], [m[0] for m in both],
                     "each pair explains part of the residual", say, notes, sets)
        if tied is not None:
            tied.extend(both)
        return None
    say(f"pairs: {'+'.join(t.effect for t in win)} added")
    return win[0].model, win[0].pb, list(win)


def _admitted(members, named: bool) -> bool:
    """The rule a pair is admitted on (its members' tests): every member
    passes for the pair named; every member explains part of the residual
    (`explains`) for a rival the record cannot tell from it, which counts
    against naming it whether or not it would pass itself (rivals_of's
    rule for single effects)."""
    return all(t.passes if named else explains(t) for t in members)


def _members(pbx, fr, current, priors) -> list:
    """Each member of the pair fitted as fr tested with every guard against
    the pair without it (the other member's model refitted with the same
    freedoms, from its prior fit): priors, (the member's test, the prior
    fit of the pair without it) for each member."""
    fit.uncertainty(pbx, fr)
    out = []
    for x, prior in priors:
        ref = reference(pbx, tuple(e for e in model.canonical(fr.effects) if e != x.effect), fr,
                        prior)
        t = guards.test(pbx, x.effect, fr, ref, so_far=current)
        t.pb = pbx
        out.append(t)
    return out


def pairs_instead(last, tests, current, cur_pb, say, notes=None, sets=None, seed=0):
    """Pairs in place of the last round's winner, not only on top of it.
    One effect can stand in for two: the nozzle's curve clamps on one side
    and bends the gain, so it follows a one-sided clip (saturation) and part
    of a dead band, both acting near the flapper's working point; a round
    then adds the one effect, and pairs tried on top of it find nothing
    (the two effects have nothing left to explain there). When the model
    chosen names that one effect and is still inadequate (its whitened
    residual depends on the input: it misses something), the pairs are
    tried where the winner was added, on the model before it with that
    round's tests (`pairs`, every guard on each member). The pairs that
    pass there (one, or several the record cannot tell apart) are weighed
    against the winner by the record (guards.distinguishable, each way),
    each side first refitted from the other's optimum and tested again:
    a pair is named when the record tells it from the winner one way only,
    the winner kept when it still passes and the record tells it one way
    only from every such pair, and neither otherwise: naming the wrong one
    would send someone to the wrong part. Pairs with the winner in them are
    not tried here (the round on top of the winner tested each such model).
    Returns (model, problem, tests to add as a round) or None (the winner
    stands as its round fitted it)."""
    win, (prev, prev_pb) = last
    # a pair with the winner in it is the winner's model with one more
    # effect: the round on top of the winner tested that already
    others = [t for t in tests or () if t.effect != win.effect]
    if sum(half_story(t) for t in others) < 2 or not guards.inadequate(cur_pb, current)[0]:
        return None
    say(f"pairs in place of {win.effect}: {current.effect} is inadequate")
    tied = []
    got = pairs(prev_pb, prev, others, say, notes, sets, seed, tied=tied)
    found = [got[2]] if got is not None else tied
    if not found:
        return None
    # each side refitted from the other's optimum, the lower kept (_pair_from,
    # _winner_from): the winner's fit comes from its round, each pair's from
    # its members' round fits, and either may sit in a basin the other's
    # optimum leads out of; weighing one side's best fit against the other's
    # first would let the search, not the record, decide which is named
    named = got is not None
    refit = [_pair_from(m, win, prev, named) for m in found]
    found = [m for m in refit if m is not None]
    if len(found) < len(refit):
        say(f"pairs: refitted from {win.effect}'s optimum, "
            f"{len(refit) - len(found)} pair(s) in its place no longer "
            + ("pass" if named else "explain part of the residual"))
    if not found:
        return None
    if named and found[0] is not got[2]:    # the one pair pairs() named, refitted
        got = found[0][0].model, found[0][0].pb, found[0]
    t = _winner_from(win, [m[0].model for m in found], prev, prev_pb, say, seed)
    names = ["+".join(x.effect for x in m) for m in found]
    # one decision over the winner and every pair that passes in its place:
    # the record must tell the one named from each other one way only (a
    # comparison that points both ways, each under its own noise model, is
    # evidence for neither: the guards' rule); else none is named
    if named and _one_way(found[0][0], t):
        say(f"pairs: {names[0]} in place of {win.effect} (the record tells them apart)")
        return got
    # the winner is kept only on a fit that passes every guard (its refit
    # from a pair's optimum is tested again as a pair's refit is); a refit
    # that fails is no evidence for a pair either, so neither is named
    if t.passes and all(_one_way(t, m[0]) for m in found):
        say(f"pairs: {win.effect} kept; the record tells it from {' and '.join(names)}")
        # the fit weighed is the one reported: the refit, with its test
        return None if t is win else (t.model, t.pb, [t])
    why = (f"{' and '.join(names)} pass{'es' if len(names) == 1 else ''} in place of "
           f"{win.effect}")
    if not t.passes:
        why += (f", and {win.effect} refitted from the pair's optimum fails: "
                + "; ".join(t.reasons[:1]))
    _cannot_tell([win.effect] + names, [t] + [m[0] for m in found], why, say, notes, sets)
    return prev, prev_pb, []


def _pair_from(members, win, prev, named=True) -> list:
    """The pair's members (their tests) with the pair refitted from the
    winner's optimum (refit_from: the winner's groups and the parameters the
    two share, the pair's own effects' sizes as fitted, a dead time placed
    on the winner's shape), retested when that fit is lower (search.lower);
    None when the retested pair no longer meets the rule it was admitted on
    (_admitted: `named`, the pair pairs() named, or a tied rival); else the
    members as they were."""
    pair, pbx = members[0].model, members[0].pb
    r = refit_from(pbx, pair.effects, pair, win.model, set(OWN[win.effect]),
                   "from " + win.effect)
    if not search.lower(r.cost, pair.cost):
        return members
    # each member against the pair without it, from the reference it had
    out = _members(pbx, r, prev, [(t, t.ref) for t in members])
    return out if _admitted(out, named) else None


def _winner_from(win, pair_fits, prev, prev_pb, say, seed=0):
    """The winner's test with its model refitted from each pair's optimum
    (from_model: the pair's groups, the winner's own size as fitted), the
    lowest tested again (_test_again: its reference searched again from the
    refit, every guard, as a round's test; the pair's refit gets the same
    in _pair_from); the winner's test itself when no refit is lower
    (search.lower)."""
    best = win.model
    for pm in pair_fits:
        own = {k for e in pm.effects for k in OWN.get(e, ())}
        r = from_model(win.pb, prev, win.effect, win.model, pm, own, "from " + pm.effect)
        if search.lower(r.cost, best.cost):
            best = r
    t = _test_again(prev_pb, prev, win, best, seed) if best is not win.model else None
    if t is None:
        return win
    _say_again(say, win, t, "refitted from the pair's optimum")
    return t


def _one_way(a, b) -> bool:
    """The record tells a's model from b's in a's favour, and not b's from
    a's."""
    return guards.distinguishable(a, b) and not guards.distinguishable(b, a)


def rivals_of(win, tests) -> list[str]:
    """The other explanations of the same residual that the record cannot
    tell from the round's winner. A rival is every other effect of the round
    that explains part of the residual, whether or not it passes the other
    guards: significant against its reference on the fit part, and
    predicting the held-out part better than its reference (one that
    predicts worse than no effect explains nothing). Whether the record
    tells it from the winner is guards.distinguishable."""
    return [t.effect for t in tests
            if t is not win and explains(t) and not guards.distinguishable(win, t)]


def _ambiguous(tests, added, lost, before, say, notes, sets):
    """The effect just added did not explain the record significantly better
    than a rival (rivals_of), and the rival adds nothing on top of it: both
    explain the same feature of the record, and the record does not say
    which is there. Naming either could send someone to take a healthy part
    apart, so neither is named: the model goes back to the one before."""
    win = next(t for t in tests if t.model is added)
    names = [t.effect for t in lost]
    others = [r for t in lost for r in tests if r.effect == t.effect]
    _cannot_tell([win.effect] + names, [win] + others,
                 f"{', '.join(names)} adds nothing on top of {win.effect}", say, notes, sets)
    return before


def _cannot_tell(names, tests, why, say, notes, sets):
    """Say that the record cannot tell these explanations apart (names[i]
    is the explanation of tests[i]'s model): in the progress, in the
    report's notes and in the JSON's `ambiguous` sets."""
    line = (f"{' or '.join(names)}: the record cannot tell which (held-out NRMSE "
            + ", ".join(f"{n} {t.model.nrmse_val:.4f}" for n, t in zip(names, tests))
            + f", not significantly different over the record; {why}), "
            "so none of them is named.")
    say("ambiguous: " + line)
    if notes is not None:
        notes.append(line)
    if sets is not None:
        sets.append(list(names))


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
