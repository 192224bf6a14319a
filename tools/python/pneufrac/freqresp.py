# SPDX-License-Identifier: MIT
"""Frequency responses of a design: the ideal irrational controller and the
one realised at fs, as `pneufrac bode` gives them."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import ideal

# The default grid of `pneufrac bode` (tools/cli/cli_bode.c): from a decade
# below the band to just under pi fs, where the held input's mean has its
# zero, 20 points per decade.
POINTS_PER_DECADE = 20
TOP = 0.99


@dataclass
class FreqResp:
    """omega (rad/s) and the complex responses P_c/E: ideal (the paper's
    transfer function at s = j omega, times the exact output line) and
    discrete (the realised controller at z = exp(j omega/fs))."""
    omega: np.ndarray
    ideal: np.ndarray
    discrete: np.ndarray
    delay_ideal: float       # dead time, s: exact
    delay_discrete: float    # dead time, s: whole samples
    title: str = ""

    def _deg(self, h, delay):
        """Unwrapped phase in degrees; the dead time's -omega T in closed
        form after the unwrapping, which a grid could not follow."""
        rot = h * np.exp(1j * self.omega * delay)
        ok = np.abs(h) > 0
        out = np.full(h.shape, np.nan)
        out[ok] = np.unwrap(np.angle(rot[ok]))
        return np.degrees(out - self.omega * delay)

    def to_frame(self):
        """pandas DataFrame with the columns of `pneufrac bode`: omega,
        ideal_db, ideal_deg, discrete_db, discrete_deg."""
        import pandas as pd
        cols = {"omega": self.omega}
        for name, h, delay in (("ideal", self.ideal, self.delay_ideal),
                               ("discrete", self.discrete, self.delay_discrete)):
            with np.errstate(divide="ignore"):
                cols[f"{name}_db"] = 20.0 * np.log10(np.abs(h))
            cols[f"{name}_deg"] = self._deg(h, delay)
        return pd.DataFrame(cols)


def default_omega(design, points: int | None = None) -> np.ndarray:
    lo = 0.1 * design.options["wb"]
    hi = TOP * np.pi * design.fs
    if points is None:
        points = int(np.ceil(POINTS_PER_DECADE * np.log10(hi / lo))) + 1
    if int(points) < 2:
        raise ValueError(f"points: {points} (at least 2)")
    return lo * (hi / lo) ** (np.arange(int(points)) / (int(points) - 1))


def freqresp(design, omega=None, points: int | None = None) -> FreqResp:
    """Ideal and realised responses of @design at @omega (rad/s, 1-D; by
    default the grid of `pneufrac bode`, @points log-spaced). Backlash,
    the nozzle curve and saturation have none: ValueError."""
    design._require_linear("freqresp")
    w = default_omega(design, points) if omega is None else np.asarray(omega, float)
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise ValueError("omega must be a 1-D array of positive finite frequencies")
    fx = design.effects
    s = 1j * w
    hi = ideal.controller(design.config, design.params, s) * ideal.line(
        fx.get("dead_time", 0.0), fx.get("lag", 0.0), s)
    hd = design._buf.freqresp(w)
    o = design.options
    title = (f"config {design.config}, fs = {design.fs:g} Hz, band [{o['wb']:g}, "
             f"{o['wh']:g}] rad/s, N = {o['order']}")
    return FreqResp(w, hi, hd, fx.get("dead_time", 0.0), design.delay / design.fs, title)
