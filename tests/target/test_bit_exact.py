# SPDX-License-Identifier: MIT
"""Golden vectors: the emulated core against the host build, bit for bit."""
from __future__ import annotations

import numpy as np
import pytest

from target_cases import CASES, RUNS, first_difference, run_id, same, stimulus

LONG = 100_000


@pytest.mark.parametrize("core,arith,bank_c,kind,case", RUNS, ids=[run_id(r) for r in RUNS])
def test_step_by_step(target_of, host, core, arith, bank_c, kind, case):
    """pf_ctrl_step_* (pf_bank_step_*) called once per sample on the
    target, the state carried in target RAM from call to call, equals the
    host's output."""
    i = CASES[kind].index(case)
    e = stimulus(arith, 3000, seed=10 + i)
    tg = target_of(core, bank_c)
    h = tg.new(arith, i, kind)
    got = np.array([tg.step(h, v) for v in e])
    want = host.run(host.new(arith, i, kind), e)
    assert same(got, want), first_difference(got, want)


@pytest.mark.parametrize("core,arith,bank_c,kind,case", RUNS, ids=[run_id(r) for r in RUNS])
def test_blocks_reset_and_long_run(target_of, host, core, arith, bank_c, kind, case):
    """A long run (pf_ctrl_run_*, pf_bank_run_*) split into blocks of
    uneven length continues across calls exactly as one host run; after a
    reset the instance starts again from rest."""
    i = CASES[kind].index(case)
    e = stimulus(arith, LONG, seed=100 + i)
    want = host.run(host.new(arith, i, kind), e)
    tg = target_of(core, bank_c)
    h = tg.new(arith, i, kind)
    cuts = [0, 1, 2, 9, 1000, 1001, 40_000, LONG]
    got = np.concatenate([tg.run(h, e[a:b]) for a, b in zip(cuts, cuts[1:])])
    assert same(got, want), first_difference(got, want)
    tg.reset(h)
    again = tg.run(h, e[:5000])
    assert same(again, want[:5000]), first_difference(again, want[:5000])
