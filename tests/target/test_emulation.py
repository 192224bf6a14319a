# SPDX-License-Identifier: MIT
"""The emulator itself: the core models and the instruction counting that
the cycle table (bench/mcu_cycles.py) rests on."""
from __future__ import annotations

import pytest
from unicorn import UC_HOOK_CODE

from mcuemu.target import Target
from mcuemu.timing import Decoder, NotArmv6m

from target_cases import stimulus


def count_per_instruction(t: Target, name: str, *args) -> int:
    n = [0]

    def one(uc, address, size, _):
        n[0] += 1

    hook = t.uc.hook_add(UC_HOOK_CODE, one)
    t.call(name, *args)
    t.uc.hook_del(hook)
    return n[0]


@pytest.mark.parametrize("core", ["m0plus", "m4"])
def test_block_counts_equal_instruction_counts(target_of, core):
    """Counting whole blocks (fast) gives the same instruction count as a
    hook on every instruction (slow), sample by sample."""
    tg = target_of(core)
    # Two instances in the same state, away from rest: one is counted
    # instruction by instruction, the other block by block.
    e = stimulus("q15", 300, seed=3)
    a, b = tg.new("q15", 1), tg.new("q15", 1)
    tg.run(a, e)
    tg.run(b, e)
    for v in (16384, -32768, 0):
        slow = count_per_instruction(tg.t, "pf_ctrl_step_q15", a.inst, v)
        profile = tg.t.start_counting()
        tg.t.call("pf_ctrl_step_q15", b.inst, v)
        tg.t.stop_counting()
        cost = tg.t.cost(profile)
        assert cost.instructions == slow
        assert cost.cycles >= cost.instructions


def test_m0plus_decoder_refuses_armv7m_code(target_of):
    """Unicorn's M-class model runs any Thumb-2 code whatever core is asked
    for, so the M0+ cycle table is what holds an M0+ image to ARMv6-M
    (every counted M0+ block goes through it): it refuses the M4 build's
    step function (Thumb-2, long multiplies) and accepts the M0+ build's."""
    m4, m0 = target_of("m4"), target_of("m0plus")
    for runner, ok in ((m0, True), (m4, False)):
        t = runner.t
        h = runner.new("q15", 1)
        profile = t.start_counting()
        t.call("pf_ctrl_step_q15", h.inst, 16384)
        t.stop_counting()
        decoder = Decoder("m0plus")
        blocks = [(a, bytes(t.uc.mem_read(a, n))) for a, n, _ in profile.edges]
        if ok:
            for a, code in blocks:
                decoder.block(a, code)
        else:
            with pytest.raises(NotArmv6m):
                for a, code in blocks:
                    decoder.block(a, code)
