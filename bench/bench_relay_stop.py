#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Saturation's placements side by side: the library's three (p_c clipped
after the relay; the relay's diaphragm on its seat; the relay's output
stopped while its memory winds on, pf_effects.h) against the blind
simulator's relay stop (bench/blindsim/plant.py, which holds z at the
limit but keeps the memory of the true p_b), on the same input and
parameters at the same internal rate. A benchmark: it measures and prints.

    .venv/bin/python bench/bench_relay_stop.py

Per configuration (the paper's example parameters, 20 kHz, a step train
that drives p_c into both limits, limits at -0.3 and +0.4 of the linear
loop's peak): the rms difference of the relay outputs over the blind
simulator's sd, the linear loops first (the discretisations alone), and
the samples the output stays at the upper limit after the input falls
from its first high step.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))

from blindsim.plant import Controller, Effects, simulate  # noqa: E402
from pneufrac import binding as lib  # noqa: E402

FS = 20000.0
N = int(0.6 * FS)
FALL = int(0.25 * FS)


def step_train() -> np.ndarray:
    k = np.arange(N)
    return np.select([k < N // 12, k < FALL, k < N // 2, k < 5 * N // 6], [0.0, 1.0, 0.0, -1.0], 0.0)


def stays(out: np.ndarray, hi: float) -> int:
    k = FALL
    while k < N and out[k] >= hi * (1 - 1e-9):
        k += 1
    return k - FALL


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.std(b))


def main() -> None:
    e = step_train()
    print("| config | linear: library vs blindsim | clip vs blindsim stop | seat vs blindsim stop "
          "| wind vs blindsim stop | at the limit after the fall: clip / seat / wind / blindsim "
          "(samples) |")
    print("|---|---|---|---|---|---|")
    for cfg in ("p", "dd", "id", "pid"):
        p = lib.default_params(cfg)
        lin = lib.Controller(cfg, p, {}, FS, t_slow=1.0).run(e)
        pk = float(np.max(np.abs(lin)))
        lo, hi = -0.3 * pk, 0.4 * pk
        ref_lin = simulate(Controller(cfg, dict(p)), Effects(), e, 1 / FS)["pc"]
        ref = simulate(Controller(cfg, dict(p)), Effects(z_lo=lo / p["k2"], z_hi=hi / p["k2"]),
                       e, 1 / FS)["pc"]
        outs = {k: lib.Controller(cfg, p, {"saturate": k, "sat_lo": lo, "sat_hi": hi}, FS,
                                  t_slow=1.0).run(e)
                for k in (lib.PF_SAT_CLIP, lib.PF_SAT_STOP, lib.PF_SAT_WIND)}
        c, s, w = outs[lib.PF_SAT_CLIP], outs[lib.PF_SAT_STOP], outs[lib.PF_SAT_WIND]
        print(f"| {cfg} | {rel(lin, ref_lin):.2e} | {rel(c, ref):.3f} | {rel(s, ref):.3f} "
              f"| {rel(w, ref):.3f} | {stays(c, hi)} / {stays(s, hi)} / {stays(w, hi)} / "
              f"{stays(ref, hi)} |")


if __name__ == "__main__":
    main()
