# SPDX-License-Identifier: MIT
"""Pairs in place of the last round's winner (branch wrong31): one
effect (the nozzle's curve) can stand in for two (a one-sided clip and a
dead band); when the model it leaves is still inadequate, the pairs are
tried where it was added, and the record decides between the pair and the
winner (selection.pairs_instead), or neither is named."""
from types import SimpleNamespace

from pneufrac_fit import guards, selection


def _case(monkeypatch, inadequate=True, pair_found=True, pair_over_win=False,
          win_over_pair=False):
    """pairs_instead over stubs: the model before the winner, the winner's
    test, and what the pairs step and the record's comparisons answer."""
    prev = SimpleNamespace(effects=(), effect="none")
    prev_pb = SimpleNamespace(name="prev_pb")
    win_model = SimpleNamespace(effects=("nozzle",), effect="nozzle", nrmse_val=0.39)
    win = SimpleNamespace(effect="nozzle", model=win_model)
    pair_model = SimpleNamespace(effects=("saturation", "backlash"),
                                 effect="saturation+backlash", nrmse_val=0.028)
    members = [SimpleNamespace(effect="saturation", model=pair_model),
               SimpleNamespace(effect="backlash", model=pair_model)]
    calls = []

    def pairs(pb, current, tests, say, notes=None, sets=None, seed=0):
        calls.append((pb, current, tests))
        return (pair_model, "pair_pb", members) if pair_found else None

    monkeypatch.setattr(selection, "pairs", pairs)
    monkeypatch.setattr(guards, "inadequate", lambda pb, fr: (inadequate, 9.0))
    monkeypatch.setattr(guards, "distinguishable",
                        lambda a, b: pair_over_win if a is members[0] else win_over_pair)
    notes, sets = [], []
    got = selection.pairs_instead((win, (prev, prev_pb)), ["round 1's tests"], win_model,
                                  "cur_pb", lambda s: None, notes, sets)
    return got, calls, notes, sets, prev, prev_pb, pair_model


def test_the_pair_replaces_the_winner_when_the_record_tells_it_apart(monkeypatch):
    got, calls, notes, _, prev, prev_pb, pair = _case(monkeypatch, pair_over_win=True)
    # the pairs were tried on the model before the winner, with its round's tests
    assert calls == [(prev_pb, prev, ["round 1's tests"])]
    assert got[0] is pair and notes == []


def test_the_winner_stays_when_the_record_tells_it_from_the_pair(monkeypatch):
    got, _, notes, _, _, _, _ = _case(monkeypatch, win_over_pair=True)
    assert got is None and notes == []


def test_neither_is_named_when_the_record_cannot_tell(monkeypatch):
    got, _, notes, sets, prev, prev_pb, _ = _case(monkeypatch)
    assert got == (prev, prev_pb, [])
    assert sets == [["nozzle", "saturation+backlash"]] and "cannot tell" in notes[0]


def test_nothing_is_tried_when_the_winner_leaves_an_adequate_model(monkeypatch):
    got, calls, _, _, _, _, _ = _case(monkeypatch, inadequate=False, pair_over_win=True)
    assert got is None and calls == []


def test_the_winner_stays_when_no_pair_passes_in_its_place(monkeypatch):
    got, calls, notes, _, _, _, _ = _case(monkeypatch, pair_found=False)
    assert got is None and len(calls) == 1 and notes == []
