# SPDX-License-Identifier: MIT
"""Forward again after a step back (selection.forward): when the backward
check drops an effect, the effects were tried on top of the model with it,
never on top of the model left. The blind simulator's
two-backlash-saturation-pid seed 1: nozzle, then saturation on top of it;
the dead band was tried on top of nozzle and of nozzle + saturation, and
failed; the backward check dropped the nozzle, and the saturation alone
was reported without the dead band ever being tried on top of it."""
from types import SimpleNamespace

from pneufrac_fit import selection


def _model(effects, nrmse):
    effects = tuple(sorted(effects))
    return SimpleNamespace(effects=effects, effect="+".join(effects) or "none",
                           nrmse_val=nrmse, k=9)


# every test's problem counts the same samples (selection.best_without)
PB = SimpleNamespace(burn=0)


def _test(effect, fr, passes):
    return SimpleNamespace(effect=effect, model=fr, ref=_model((), 1.0), passes=passes,
                           excludes=passes, val_gain=0.1 if passes else -0.1, val_z=3.0 if passes else -3.0,
                           reasons=[] if passes else ["stub: fails"], pb=PB)


def _run(monkeypatch, dead_band_on_saturation: bool):
    sat = _model(("saturation",), 0.2)
    both = _model(("nozzle", "saturation"), 0.19)
    sat_db = _model(("backlash", "saturation"), 0.05)
    script = {
        "none": [_test("nozzle", _model(("nozzle",), 0.33), True)],
        "nozzle": [_test("saturation", both, True), _test("backlash", _model((), 1), False)],
        "nozzle+saturation": [_test("backlash", _model((), 1), False)],
        "saturation": [_test("backlash", sat_db, dead_band_on_saturation)],
        "backlash+saturation": [_test("nozzle", _model((), 1), False)],
    }
    calls = []

    def run_round(pb, cur, eff, seed, jobs, say, prev):
        calls.append(cur.effect)
        return script[cur.effect]

    def backward(pb, fr, say):       # the nozzle fails beside saturation
        return (sat if fr is both else fr), pb, [SimpleNamespace(effect=e, dbic=-1.0)
                                                 for e in ("saturation",)]
    monkeypatch.setattr(selection, "run_round", run_round)
    monkeypatch.setattr(selection, "backward", backward)
    monkeypatch.setattr(selection, "pairs", lambda *a, **k: None)
    monkeypatch.setattr(selection, "pairs_instead", lambda *a, **k: None)
    monkeypatch.setattr(selection, "best_same_fit", lambda tests, cur, pb: (cur, pb, ""))
    # the scripted fits are the rounds' last word: none refined or refitted
    monkeypatch.setattr(selection, "refine_winner", lambda pb, cur, tests, seed, say: tests)
    monkeypatch.setattr(selection, "from_better", lambda pb, cur, tests, seed, say: tests)
    final, _, rounds, checks = selection.forward(PB, _model((), 1.0), 0, 1, lambda s: None)
    return final, calls, checks


def test_effects_are_tried_on_top_of_the_model_the_backward_check_leaves(monkeypatch):
    final, calls, _ = _run(monkeypatch, True)
    assert calls == ["none", "nozzle", "nozzle+saturation", "saturation",
                     "backlash+saturation"]
    assert final.effects == ("backlash", "saturation")


def test_nothing_added_there_keeps_the_backward_checks(monkeypatch):
    final, calls, checks = _run(monkeypatch, False)
    assert calls == ["none", "nozzle", "nozzle+saturation", "saturation"]
    assert final.effects == ("saturation",) and [t.effect for t in checks] == ["saturation"]
