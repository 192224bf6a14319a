# SPDX-License-Identifier: MIT
"""Watchdog: without a write of e, sp or pv within watchdog_ms the output
goes to failsafe_out and status bit 1 is set; the next write recovers.
In lockstep the timeout is counted in samples, so the trip is exact."""

from pfd import Regs, f32, simulate_exchanges, wait_until

TRIPPED = 1 << 1


def commit_bump_tau(r, tau):
    r.write("bump_tau", tau)
    r.write("commit", 1)
    r.tick(1)  # switched in at rest


def test_trip_and_recovery_exact(daemon):
    """fs = 1 kHz, watchdog 10 ms = 10 samples; bump_tau = 0 so that after
    recovery the output is the controller's own, which never stopped."""
    d = daemon("--clock", "external")
    r = Regs(d.client())
    commit_bump_tau(r, 0.0)
    ref = simulate_exchanges(1000, r.read("substeps_used"), "--config", "dd", "--duration", "0.2")
    r.write("failsafe_out", 0.005)
    r.write("watchdog_ms", 10)
    r.write("e", 1.0)  # refresh
    pcs = []
    for k in range(10):
        r.tick(1)
        assert not r.read("status") & TRIPPED, k
        pcs.append(r.read("pc"))
    r.tick(1)  # 10 samples without a write: trips at this one
    st = r.read("status")
    assert st & TRIPPED
    assert r.read("pc") == f32(0.005)
    assert r.read("watchdog_trips") == 1
    for _ in range(50):
        r.tick(1)
        assert r.read("pc") == f32(0.005)
    assert r.read("status") & TRIPPED
    r.write("e", 1.0)  # writes resume
    r.tick(1)
    assert not r.read("status") & TRIPPED
    # The controller ran on through the trip: sample 62 of the step.
    assert abs(r.read("pc") - float(ref[61]["pc"])) <= 1e-6
    assert r.read("watchdog_trips") == 1
    assert all(abs(a - float(row["pc"])) <= 1e-6 for a, row in zip(pcs, ref))


def test_recovery_is_bumpless(daemon):
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("failsafe_out", 0.002)
    r.write("watchdog_ms", 5)
    r.write("e", 1.0)
    r.tick(400)
    assert r.read("status") & TRIPPED
    assert r.read("pc") == f32(0.002)
    r.write("e", 1.0)
    prev = r.read("pc")
    steps = []
    for _ in range(200):
        r.write("e", 1.0)  # keep the watchdog fed
        r.tick(1)
        pc = r.read("pc")
        steps.append(abs(pc - prev))
        prev = pc
    # Bleeds from 0.002 towards ~0.009 with bump_tau = 1 s: about 7e-6 per
    # sample at 1 kHz, never the 0.007 jump of an abrupt return.
    assert steps[0] < 2e-5
    assert max(steps) < 2e-5
    assert r.read("status") & (1 << 10)  # transfer in progress


def test_zero_disables(daemon):
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("e", 1.0)
    r.tick(5000)
    assert not r.read("status") & TRIPPED
    assert r.read("watchdog_trips") == 0


def test_sp_pv_writes_refresh_too(daemon):
    d = daemon("--clock", "external")
    r = Regs(d.client())
    r.write("input_sel", 1)
    r.write("watchdog_ms", 3)
    for _ in range(20):
        r.write("pv", 0.25)
        r.tick(2)
        assert not r.read("status") & TRIPPED
    r.tick(3)
    assert r.read("status") & TRIPPED


def test_real_time_trip_and_recovery(daemon):
    """Internal clock: generous margins, no tight timing."""
    d = daemon()
    r = Regs(d.client())
    r.write("failsafe_out", 0.004)
    r.write("watchdog_ms", 100)
    r.write("e", 0.5)
    wait_until(lambda: r.read("status") & TRIPPED, 10, "watchdog trip", step=0.05)
    assert r.read("pc") == f32(0.004)
    r.write("e", 0.5)
    wait_until(lambda: not r.read("status") & TRIPPED, 10, "watchdog recovery",
               between=lambda: r.write("e", 0.5))
