# SPDX-License-Identifier: MIT
"""Pairs in place of a single winner, each side refitted from the other's
optimum (analysis-bench.md, branch pairs32; the wrong31 review's R1).
pairs_instead weighs a pair that passes where the winner was added against
the winner; the winner's fit comes from its round and the pair's from its
members' round fits, and either may stop in a basin the other's optimum
leads out of. Each side is refitted from the other's optimum, the lower
kept, before the record weighs them.

The record: the tool's generator, p with a lag (test_converge's). Fits
short of their optimum are made by a few iterations from a poor start, as
test_converge makes them."""
from types import SimpleNamespace

from pneufrac_fit import guards, search, selection
from test_converge import _fit, _problem, _start


def _records():
    pb = _problem()
    base = _fit(pb, (), _start(pb))
    good = _fit(pb, ("lag",), _start(pb, lag=0.01))
    return pb, base, good


def test_the_winner_is_refitted_from_the_pairs_optimum_when_that_is_lower():
    """A lag winner that stopped short (12 iterations from a poor start),
    a pair (lag + dead band) at the record's optimum: the winner refitted
    from the pair's groups ends lower, and its test is made again on that
    fit as a round's test is (selection._test_again: the reference searched
    again from the refit, every guard), the round's reference kept among
    the models it must beat."""
    pb, base, good = _records()
    poor = _fit(pb, ("lag",), _start(pb, lag=0.05, K=0.5 * good.values["K"]), budget=12)
    assert search.lower(good.cost, poor.cost)      # the premise: the winner stopped short
    win = selection.try_effect(pb, base, "lag", 1, fitted=poor)
    pbx = selection.problem_for(pb, ("lag", "backlash"))
    pair = _fit(pbx, ("lag", "backlash"),
                {**good.groups, **good.values, "deadband": 0.002 * pb.span_e})
    said = []
    got = selection._winner_from(win, [pair], base, pb, said.append)
    assert got is not win and isinstance(got, guards.Test) and got.effect == "lag"
    assert search.lower(got.model.cost, poor.cost)
    assert got.ref is not win.ref and any(r is win.ref for r in got.also_without)
    assert got.passes                          # the record's own effect, at its optimum
    assert any("refitted from the pair's optimum" in s for s in said)


def test_a_winner_at_its_optimum_is_left_as_it_is():
    """The winner at the record's optimum: no refit from a pair's optimum is
    lower, so its own test is returned (nothing refitted, nothing said)."""
    pb, base, good = _records()
    win = selection.try_effect(pb, base, "lag", 1, fitted=good)
    pbx = selection.problem_for(pb, ("lag", "backlash"))
    far = _fit(pbx, ("lag", "backlash"), _start(pbx, lag=0.05, deadband=0.05 * pb.span_e),
               budget=6)
    said = []
    assert selection._winner_from(win, [far], base, pb, said.append) is win and said == []


def test_pairs_instead_keeps_the_winner_on_the_fit_it_weighed(monkeypatch):
    """pairs_instead with the real refits (_pair_from, _winner_from): a lag
    winner that stopped short, a pair at the record's optimum in its place,
    and a record that tells the one-effect model from the pair (stubbed on
    the models' effects, not on the objects, which the refits replace).
    The winner is kept on its refit from the pair's optimum, and that fit,
    the one weighed, is the one returned, with its test (review of pairs32,
    item 2); ignoring the refit would return None (the round's fit)."""
    pb, base, good = _records()
    poor = _fit(pb, ("lag",), _start(pb, lag=0.05, K=0.5 * good.values["K"]), budget=12)
    win = selection.try_effect(pb, base, "lag", 1, fitted=poor)
    pbx = selection.problem_for(pb, ("lag", "backlash"))
    pair = _fit(pbx, ("lag", "backlash"),
                {**good.groups, **good.values, "deadband": 0.002 * pb.span_e})
    members = _members(pbx, base, pair)
    monkeypatch.setattr(selection, "pairs", lambda *a, **k: (pair, pbx, members))
    monkeypatch.setattr(guards, "inadequate", lambda pb_, fr: (True, 9.0))
    monkeypatch.setattr(guards, "distinguishable",
                        lambda a, b: len(a.model.effects) < len(b.model.effects))
    others = [SimpleNamespace(effect=e, excludes=True) for e in ("backlash", "nozzle")]
    said = []
    got = selection.pairs_instead((win, (base, pb)), others, poor, pb, said.append)
    assert got is not None
    fr, pb_got, tests = got
    assert fr.effects == ("lag",) and search.lower(fr.cost, poor.cost)
    assert len(tests) == 1 and tests[0].model is fr and tests[0].passes and pb_got is tests[0].pb
    assert any("lag kept" in s for s in said)


def _members(pbx, base, fr):
    """The pair's members tested as pairs() tests them."""
    lag = _fit(pbx, ("lag",), {**fr.groups, **fr.values})
    band = _fit(pbx, ("backlash",), {**fr.groups, **fr.values})
    return selection._members(pbx, fr, base, ((SimpleNamespace(effect="lag"), band),
                                              (SimpleNamespace(effect="backlash"), lag)))


def test_a_refitted_pair_is_judged_by_the_rule_it_was_admitted_on():
    """A pair (lag + dead band) that stopped short, the lag winner at its
    optimum: the pair refitted from the winner's groups ends lower, and its
    members are tested again on that fit, each against the pair without it
    on the pair's problem. The record has no dead band: on the lower fit the
    dead band explains part of the residual but fails a guard. So the pair
    pairs() named (every member must pass) is gone, and a tied rival (every
    member must explain: pairs()'s rule for rivals) stays, with its new
    tests (review of pairs32, item 3)."""
    pb, base, good = _records()
    win = selection.try_effect(pb, base, "lag", 1, fitted=good)
    pbx = selection.problem_for(pb, ("lag", "backlash"))
    poor = _fit(pbx, ("lag", "backlash"),
                _start(pbx, lag=0.05, deadband=0.02 * pb.span_e, K=0.5 * good.values["K"]),
                budget=12)
    members = _members(pbx, base, poor)
    assert selection._pair_from(members, win, base, named=True) is None
    got = selection._pair_from(members, win, base, named=False)
    assert got is not None and got is not members
    assert search.lower(got[0].model.cost, poor.cost)
    assert [t.effect for t in got] == ["lag", "backlash"]
    assert all(t.model is got[0].model and t.pb is pbx for t in got)
    # each member against the pair without it
    assert [t.ref.effects for t in got] == [("backlash",), ("lag",)]
    assert all(selection.explains(t) for t in got) and not all(t.passes for t in got)


def test_a_pair_at_its_optimum_keeps_its_members_tests():
    """A winner whose groups and shared values are the pair's own, the pair
    at its optimum: the refit starts where the pair is and finds nothing
    lower, so the members' tests are returned as they were."""
    pb, base, good = _records()
    pbx = selection.problem_for(pb, ("lag", "backlash"))
    st = {**good.groups, **good.values, "deadband": 0.002 * pb.span_e}
    pair = search.refine(pbx, ("lag", "backlash"), [("pair", st)], iters=4 * search.REFINE_ITER)
    pair = search.refine(pbx, ("lag", "backlash"), [("on", {**pair.groups, **pair.values})],
                         iters=4 * search.REFINE_ITER)
    members = _members(pbx, base, pair)
    win = SimpleNamespace(effect="lag", model=SimpleNamespace(
        groups=dict(pair.groups), values={k: v for k, v in pair.values.items()
                                          if k != "deadband"}))
    assert selection._pair_from(members, win, base) is members
