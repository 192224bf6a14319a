# SPDX-License-Identifier: MIT
"""What the linear model leaves out, defined as in pf_effects.h and
docs/analysis.md, with the parameters in pneufrac-fit's units:

- backlash: a play operator on the flapper displacement x; `deadband` is
  the full width of the dead band in input units (x / ce, ce = b/(a+b));
- nozzle: p_b/p_s = F(u) = 1/(1+u^2) of the normalised gap u = u0 + x/x_half,
  scaled to unit slope at the bias point u0, so that the linear gain k1 is
  the small-signal gain there; `nozzle_xh` is x_half in input units. The
  library fixes u0 at the inflection 1/sqrt(3); here u0 is set by the
  equilibrium and may lie elsewhere. The gap cannot close below u = 0;
- saturation: p_c clipped to [sat_lo, sat_hi] (absolute output units)
  inside the loop, so the bellows see the clipped pressure; the relay's
  memory runs on with its own unclipped z, or (sat_wind) the stop holds
  the stroke z the diaphragm drives while the diaphragm stays loaded by
  the whole p_b: its integral of p_b - pmin z sees the held z and winds
  on for as long as the stop holds (controller.build);
- lag: a first-order lag of time constant `lag` (s) on the output line;
- dead_time: a transport delay (s) on the output line, after the lag.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

U0_INFLECTION = 1.0 / math.sqrt(3.0)


@dataclass
class Effects:
    deadband: float = 0.0        # full width, input units; 0 = off
    backlash_side: float = 0.0   # where the play rests at the start, in half-widths (-1..1)
    nozzle_xh: float = 0.0       # x_half, input units; 0 = linear nozzle (eq. 9)
    nozzle_u0: float = U0_INFLECTION
    sat_lo: float = -math.inf    # absolute output units
    sat_hi: float = math.inf
    sat_wind: bool = False       # the relay's memory winds on at a limit
    lag: float = 0.0             # s
    dead_time: float = 0.0       # s

    def in_loop(self) -> bool:
        return self.deadband > 0 or self.nozzle_xh > 0 or self.saturates()

    def saturates(self) -> bool:
        return math.isfinite(self.sat_lo) or math.isfinite(self.sat_hi)

    def names(self) -> list[str]:
        """Causes present, in pneufrac-fit's names."""
        out = []
        if self.dead_time > 0:
            out.append("dead_time")
        if self.lag > 0:
            out.append("lag")
        if self.saturates():
            out.append("saturation")
        if self.deadband > 0:
            out.append("backlash")
        if self.nozzle_xh > 0:
            out.append("nozzle")
        return out


def play(prev: float, x: float, r: float) -> float:
    """Play operator of half-width r: stays at prev until x is more than r
    away, then follows at distance r."""
    return min(max(prev, x - r), x + r)


def nozzle_F(u):
    return 1.0 / (1.0 + np.square(u))


def nozzle_slope(u):
    """dF/du."""
    return -2.0 * u / np.square(1.0 + np.square(u))


def nozzle(dx, xh: float, u0: float):
    """Back-pressure change per k1, h(dx) = xh (F(u0) - F(u0 + dx/xh)) / |F'(u0)|:
    unit slope at dx = 0, increasing, the gap clamped at u >= 0."""
    u = np.maximum(u0 + np.asarray(dx, dtype=float) / xh, 0.0)
    return xh * (nozzle_F(u0) - nozzle_F(u)) / abs(nozzle_slope(u0))


def nozzle_max_slope(u0: float) -> float:
    """Largest slope of h: |F'| peaks at the inflection."""
    return abs(nozzle_slope(U0_INFLECTION)) / abs(nozzle_slope(u0))


def delay(sig: np.ndarray, fs: float, d: float, rest: float = 0.0) -> np.ndarray:
    """sig(t - d) on the same uniform grid, linear interpolation between
    samples (the grid is fine enough: it is the internal rate); before the
    first sample the line holds `rest`."""
    if d <= 0.0:
        return sig.copy()
    t = np.arange(sig.size) / fs - d
    out = np.interp(t, np.arange(sig.size) / fs, sig)
    out[t < 0.0] = rest
    return out
