# SPDX-License-Identifier: MIT
"""The simulator's step response against the exact one in tests/ref
(paper_step_exact.csv, paper_step_cases.json): shared by the test and the
accuracy benchmark."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from . import simulate
from .effects import Effects


def load(ref_dir: Path) -> tuple[dict, np.ndarray]:
    """(cases, exact table) from the repository's reference directory."""
    with open(Path(ref_dir) / "paper_step_cases.json") as f:
        cases = json.load(f)
    exact = np.genfromtxt(Path(ref_dir) / "paper_step_exact.csv", delimiter=",", names=True,
                          deletechars="")
    return cases, exact


def step_error(spec: dict, t_ref: np.ndarray, y_ref: np.ndarray, fs_int: float,
               window: tuple[float, float] = (1e-3, 5.0)) -> tuple[float, float]:
    """Largest |simulated - exact| over the window, relative to the peak
    |exact| there, and where it occurs. The unit step is applied at t = 0;
    the simulation runs on the internal grid and is read at the
    reference's times by a cubic spline."""
    p = {k: float(v) for k, v in spec["params"].items()}
    n = int(window[1] * fs_int) + 4
    run = simulate.run(spec["config"], p, Effects(), np.ones(n), fs_int)
    sel = (t_ref >= window[0]) & (t_ref <= window[1])
    sim = CubicSpline(np.arange(n) / fs_int, run.line)(t_ref[sel])
    err = np.abs(sim - y_ref[sel])
    k = int(np.argmax(err))
    return float(err[k] / np.max(np.abs(y_ref[sel]))), float(t_ref[sel][k])
