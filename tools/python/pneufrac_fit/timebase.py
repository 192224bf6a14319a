# SPDX-License-Identifier: MIT
"""Time stamps as historians and DAQ cards write them: one sample per
period, each stamp off its grid point by some jitter, and now and then a
gap where samples are missing.

A step between stamps of 0.5 to 1.5 periods is one sample; a longer one is
a gap of round(step / period) - 1 missing samples; a shorter one is
refused. The period is the least-squares slope of t against the sample
index over the longest gap-free stretch, and every stamp of that stretch
must lie within JITTER_TOL periods of its grid point: that is the jitter
accepted (a quarter of a period either way, so that no stamp is closer to
a neighbour's grid point than to its own). Beyond it the record is refused
as irregular sampling.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

JITTER_TOL = 0.25      # periods, either way
GAP_STEP = 1.5         # a step longer than this many periods is a gap
MIN_STEP = 0.5         # a step shorter than this many periods is refused


class TimebaseError(ValueError):
    pass


@dataclass
class Gap:
    index: int          # first sample after the gap (in the input record)
    t: float            # time stamp of that sample
    duration: float     # s between the stamps around the gap
    missing: int        # samples missing


@dataclass
class Timebase:
    fs: float
    start: int                       # the stretch used: [start, stop)
    stop: int
    gaps: list = field(default_factory=list)
    jitter_rms: float = 0.0          # periods
    jitter_max: float = 0.0          # periods

    def notes(self, n_total: int) -> list[str]:
        out = []
        if self.jitter_max > 1e-3:
            out.append(f"time stamps jitter by {100 * self.jitter_rms:.2g} % of a period rms "
                       f"({100 * self.jitter_max:.2g} % at most; accepted up to "
                       f"{100 * JITTER_TOL:.0f} %): samples taken as uniform at {self.fs:.6g} Hz")
        for g in self.gaps:
            out.append(f"GAP in the record at t = {g.t:.6g} s (sample {g.index}): "
                       f"{g.duration:.4g} s between stamps, {g.missing} sample(s) missing")
        if self.gaps:
            out.append(f"analysed the longest stretch without gaps: samples {self.start} to "
                       f"{self.stop - 1} ({self.stop - self.start} of {n_total}); the rest is "
                       "not used (the controller's state across a gap is unknown)")
        return out


def analyse(t: np.ndarray, source: str = "<data>") -> Timebase:
    t = np.asarray(t, float)
    dt = np.diff(t)
    bad = np.flatnonzero(~(dt > 0))
    if bad.size:
        k = int(bad[0])
        raise TimebaseError(f"{source}: t is not strictly increasing at sample {k + 1} "
                            f"(t = {t[k]:.9g} then {t[k + 1]:.9g})")
    T0 = float(np.median(dt))
    short = np.flatnonzero(dt < MIN_STEP * T0)
    if short.size:
        k = int(short[0])
        raise TimebaseError(
            f"{source}: non-uniform sampling: step {k + 1} is {dt[k]:.9g} s, under half "
            f"the typical step {T0:.9g} s (irregular sampling; resample first)")
    cut = np.flatnonzero(dt > GAP_STEP * T0)
    gaps = [Gap(int(k + 1), float(t[k + 1]), float(dt[k]), int(round(dt[k] / T0)) - 1)
            for k in cut]
    bounds = [0] + [g.index for g in gaps] + [t.size]
    lens = np.diff(bounds)
    i = int(np.argmax(lens))
    a, b = bounds[i], bounds[i + 1]
    seg = t[a:b]
    k = np.arange(seg.size, dtype=float)
    if seg.size >= 2:
        T, t0 = np.polyfit(k, seg, 1)
    else:
        T, t0 = T0, float(seg[0])
    dev = (seg - (t0 + T * k)) / T
    jmax = float(np.max(np.abs(dev))) if dev.size else 0.0
    if jmax > JITTER_TOL:
        j = int(np.argmax(np.abs(dev)))
        raise TimebaseError(
            f"{source}: non-uniform sampling: sample {a + j} is {jmax:.2f} periods off a "
            f"uniform grid of {T:.9g} s (jitter up to {JITTER_TOL:g} of a period is "
            "accepted; resample first)")
    return Timebase(1.0 / T, a, b, gaps, float(np.sqrt(np.mean(dev * dev))), jmax)
