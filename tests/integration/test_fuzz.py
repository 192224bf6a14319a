# SPDX-License-Identifier: MIT
"""Fuzzing: at least 100 000 random and malformed ADUs over several
connections (fuzz_modbus.py). The daemon stays up, every request of a
well-behaved client is answered correctly throughout (a missing answer is
one that has not come within HANG_S: a hang, not slowness; the response
times are printed, not asserted), and the loop's sample counter keeps
advancing. CTest runs this alone (RUN_SERIAL), in the Release and the
ASan/UBSan builds."""

from fuzz_modbus import run
from pfd import HANG_S, SLOW, Regs


def test_fuzz(daemon):
    d = daemon("--instances", "2", "--max-clients", "32", run_for=900)
    r = run(d.port, adus=100000, workers=4, min_seconds=10, max_seconds=300 * SLOW,
            hang_seconds=HANG_S)
    summary = {k: v for k, v in r.items() if k != "samples"}
    print(summary)
    assert d.proc.poll() is None, d.log()[-2000:]
    assert r["adus"] >= 100000, summary
    assert r["reconnects"] > 100, summary  # the malformed frames did get the daemon to drop them
    assert r["slow_answered"] > 0, summary
    assert r["monitor_failures"] == 0, summary
    assert r["monitor_requests"] > 100, summary
    # The sample counter never goes back, and no stretch of HANG_S passes
    # without it advancing (the loop did not hang).
    samples = r["samples"]
    assert all(b[1] >= a[1] for a, b in zip(samples, samples[1:]))
    t_first = samples[0][0]
    for i, (t, n) in enumerate(samples):
        later = [m for (u, m) in samples[i:] if u >= t + HANG_S]
        if later:
            assert later[0] > n, (t - t_first, n, later[0])
    # Still serving, and it stops cleanly (sanitizers report at exit).
    assert Regs(d.client()).read("samples") > samples[-1][1]
    assert d.stop() == 0, d.log()[-2000:]
