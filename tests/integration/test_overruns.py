# SPDX-License-Identifier: MIT
"""Overrun warnings are aggregated across instances and rate-limited: one
msg=overruns line per --overrun-report-s at most, with a count per
instance and the worst lateness, and every overrun in exactly one line.
The loop is made late on purpose, deterministically: the whole daemon is
stopped (SIGSTOP) for 100 ms three times while 8 instances run at
10 kHz, which misses about 1000 periods of each instance each time. (One
line per instance every 200 ms, as before, logged about 400 lines in 3 s
for this load without any pause.)"""

import datetime
import os
import re
import signal
import time

from pfd import SLOW

INSTANCES = 8      # few enough that an ASan build on a busy machine passes the start-up load check
PAUSE_S = 0.1


def parse(line):
    ts = re.search(r"ts=(\S+)Z ", line).group(1)
    fields = dict(re.findall(r"(\w+)=(\S+)", line.split(" msg=overruns ", 1)[1]))
    units = {int(u): int(n) for u, n in (p.split(":") for p in fields["units"].split(","))}
    return (datetime.datetime.fromisoformat(ts).timestamp(), int(fields["overruns"]),
            float(fields["worst_late_us"]), units)


def test_one_line_per_interval_and_every_overrun_counted(daemon):
    d = daemon("--instances", str(INSTANCES), "--fs", "10000", "--overrun-report-s", "1",
               "--loop-budget", "95")
    t0 = time.monotonic()
    for _ in range(3):
        time.sleep(0.8)
        os.kill(d.proc.pid, signal.SIGSTOP)
        time.sleep(PAUSE_S)
        os.kill(d.proc.pid, signal.SIGCONT)
    time.sleep(0.5)
    assert d.stop() == 0
    elapsed = time.monotonic() - t0
    log = d.log()
    lines = [parse(line) for line in log.splitlines() if " msg=overruns " in line]
    total = int(re.search(r"msg=loop-stats .* overruns=(\d+)", log).group(1))
    print(f"{len(lines)} overrun lines in {elapsed:.1f} s, {total} overruns")

    # At most one line a second: the first at the first overrun, then a
    # second or more apart, and one more at stop.
    assert 1 <= len(lines) <= elapsed / 1.0 + 2
    stamps = [t for t, _, _, _ in lines[:-1]]
    assert all(b - a >= 0.999 for a, b in zip(stamps, stamps[1:])), stamps
    # Each line's count is its instances' sum, and the lines add up to the
    # loop's own total: nothing lost, nothing counted twice.
    per_unit = {}
    for _, n, _, units in lines:
        assert n == sum(units.values())
        for u, k in units.items():
            per_unit[u] = per_unit.get(u, 0) + k
    assert sum(n for _, n, _, _ in lines) == total
    # Every instance missed about 1000 periods in each pause, and a pause
    # made a sample late by about its length.
    assert sorted(per_unit) == list(range(1, INSTANCES + 1))
    assert min(per_unit.values()) >= 3 * 0.5 * PAUSE_S * 10000
    assert max(late for _, _, late, _ in lines) >= 0.5 * PAUSE_S * 1e6
    assert elapsed < 60 * SLOW


def test_no_line_without_overruns(daemon):
    """In lockstep nothing is ever late."""
    d = daemon("--clock", "external", "--instances", "4", "--overrun-report-s", "1")
    time.sleep(1.5)
    assert d.stop() == 0
    assert " msg=overruns " not in d.log()
