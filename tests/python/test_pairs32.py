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
    fit (every guard, against the winner's own reference)."""
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
    assert got.ref is win.ref                  # against the winner's own reference
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


def _members(pbx, base, fr):
    """The pair's members tested as pairs() tests them."""
    lag = _fit(pbx, ("lag",), {**fr.groups, **fr.values})
    band = _fit(pbx, ("backlash",), {**fr.groups, **fr.values})
    return selection._members(pbx, fr, base, ((SimpleNamespace(effect="lag"), band),
                                              (SimpleNamespace(effect="backlash"), lag)))


def test_a_pair_short_of_its_optimum_is_refitted_from_the_winners_and_tested_again():
    """A pair (lag + dead band) that stopped short, the lag winner at its
    optimum: the pair refitted from the winner's groups ends lower, and its
    members are tested again on that fit. The record has no dead band, so
    the refitted pair is either gone (a member fails: None) or its members'
    tests are new ones on a lower fit; never the old tests."""
    pb, base, good = _records()
    win = selection.try_effect(pb, base, "lag", 1, fitted=good)
    pbx = selection.problem_for(pb, ("lag", "backlash"))
    poor = _fit(pbx, ("lag", "backlash"),
                _start(pbx, lag=0.05, deadband=0.02 * pb.span_e, K=0.5 * good.values["K"]),
                budget=12)
    members = _members(pbx, base, poor)
    got = selection._pair_from(members, win, base)
    assert got is not members
    if got is not None:
        assert search.lower(got[0].model.cost, poor.cost)
        assert {t.effect for t in got} == {"lag", "backlash"}
        assert all(t.passes for t in got)


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
