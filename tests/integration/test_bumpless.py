# SPDX-License-Identifier: MIT
"""Bumpless commit and manual/auto transfer (docs/pneufracd.md): the first
sample after a switch differs from the last before by no more than the
controller's normal one-sample change, and the difference between the
old and new parameter sets then bleeds off with time constant bump_tau."""

import math

from pfd import Regs, wait_until


def run(r, n):
    out = []
    for _ in range(n):
        r.tick(1)
        out.append(r.read("pc"))
    return out


def test_commit_is_bumpless(daemon):
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("e", 1.0)
    before = run(r, 300)
    normal = max(abs(b - a) for a, b in zip(before[-50:], before[-49:]))
    # A different bellows order: q 0.9 -> 0.7 changes the settled output.
    r.write("q", 0.7)
    r.write("commit", 1)
    after = run(r, 1)
    assert r.read("status") & (1 << 10)  # the transfer offset is running
    after += run(r, 2999)
    first_step = abs(after[0] - before[-1])
    assert first_step <= normal, (first_step, normal)
    assert r.read("committed_q") == r.read("q")
    # The offset bleeds off: per-sample changes stay small compared with
    # the jump an abrupt switch would make.
    jump = abs(after[-1] - before[-1])
    steps = [abs(b - a) for a, b in zip(after, after[1:])]
    assert max(steps) < 0.05 * jump + normal, (max(steps), jump)
    assert not (r.read("status") & (1 << 8))  # switched in
    # bump_tau 1 s = 1000 samples: 30 more time constants take the offset
    # (e^-30 of the jump) below the daemon's cut-off of 1e-9 out_fs, so
    # the transfer must be over (status bit 10).
    r.tick(30000)
    assert not (r.read("status") & (1 << 10))


def test_commit_without_bleed_jumps(daemon):
    """bump_tau = 0 disables the transfer: documented, and visible."""
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("bump_tau", 0.0)
    r.write("commit", 1)
    r.write("e", 1.0)
    before = run(r, 300)
    r.write("q", 0.7)
    r.write("commit", 1)
    after = run(r, 2)
    # The first sample is still the old set's (exact hand-over), the
    # second is the new set's own output.
    assert abs(after[0] - before[-1]) < 1e-5
    assert abs(after[1] - after[0]) > 1e-4


def test_manual_to_auto_is_bumpless(daemon):
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("e", 1.0)
    run(r, 200)
    r.write("manual_out", 0.003)
    r.write("mode", 1)
    man = run(r, 50)
    assert all(v == r.read("manual_out") for v in man)
    assert r.read("status") & (1 << 3)
    r.write("mode", 0)
    back = run(r, 100)
    assert abs(back[0] - man[-1]) < 2e-5
    assert all(abs(b - a) < 2e-5 for a, b in zip(back, back[1:]))


def test_commit_in_real_time(daemon):
    """Internal clock: the switch happens within a sample or so."""
    d = daemon()
    r = Regs(d.client())
    r.write("e", 0.5)
    r.write("RC", 0.02)
    r.write("commit", 1)
    assert math.isclose(r.read("committed_RC"), 0.02, rel_tol=1e-6)
    wait_until(lambda: not r.read("status") & (1 << 8), 10, "commit switched in")
    assert r.read("commits") == 1
