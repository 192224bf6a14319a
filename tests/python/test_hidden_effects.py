# SPDX-License-Identifier: MIT
"""Hide effects in records the fit's own model does not make in the same
way (cases.PLANT: 10x the data rate, Oustaloup order 5, perturbed
parameters) and require the diagnosis to find them: the right causes, the
parameters within cases' tolerances, the validation NRMSE at least halfway
from the baseline's to the noise floor. Clean records must give none.

Every configuration (pid included) gets a clean record and three effects,
and every effect appears in at least two configurations; the full matrix
and more seeds run in bench/bench_fit.py (docs/analysis-bench.md)."""
import pytest

import cases

MATRIX = [
    ("p", "none"), ("p", "dead_time"), ("p", "backlash"), ("p", "nozzle"),
    ("dd", "none"), ("dd", "lag"), ("dd", "saturation"), ("dd", "backlash"),
    ("id", "none"), ("id", "dead_time"), ("id", "nozzle"), ("id", "saturation"),
    ("pid", "none"), ("pid", "lag"), ("pid", "backlash"), ("pid", "dead_time"),
]


@pytest.mark.parametrize("config,effect", MATRIX)
def test_hidden_effect_is_found(config, effect):
    seed = 100 + 10 * ["p", "dd", "id", "pid"].index(config) + cases_index(effect)
    ds = cases.make(config, effect, seed)
    d = cases.run(ds)
    bad = cases.check(ds, d)
    assert not bad, f"seed {seed}: " + "; ".join(bad) + " | " + cases.explain(ds, d)


def cases_index(effect):
    return ["none", "dead_time", "lag", "saturation", "backlash", "nozzle"].index(effect)
