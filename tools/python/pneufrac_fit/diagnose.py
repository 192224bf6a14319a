# SPDX-License-Identifier: MIT
"""The diagnosis: baseline fit, what it gets wrong, the causes, the gain."""
from __future__ import annotations

import math
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from . import baseline as base_mod
from . import evidence as ev_mod
from . import candidates, data, fit, guards, model, noise, selection, signals
from . import holdout as holdout_mod
from .fit import FitResult, Problem



class Progress:
    def __init__(self, enabled: bool = True):
        self.enabled = enabled
        self.t0 = time.monotonic()

    def __call__(self, msg: str) -> None:
        if self.enabled:
            print(f"[pneufrac-fit {time.monotonic() - self.t0:6.1f}s] {msg}",
                  file=sys.stderr, flush=True)


@dataclass
class Diagnosis:
    config: str
    fs: float
    n: int
    split: object                # holdout.Split: the fit parts and held-out blocks
    baseline: FitResult
    extended: FitResult
    causes: list                # effect names, most important first
    tests: list                 # guards.Test of round 1 (every effect on the baseline)
    rounds: list                # every round's tests
    checks: list                # the final tests of the named effects
    identified: dict
    fixed_reason: dict
    evidence: list
    why: list
    ev_before: dict = field(default_factory=dict)
    ev_after: dict = field(default_factory=dict)
    noise_sd: float = math.nan          # white (sample-to-sample) part
    noise_model: object = None          # AR model of the final residual
    noise_floor_val: float = math.nan
    noise_floor_source: str = ""
    record_notes: list = field(default_factory=list)
    fit_notes: list = field(default_factory=list)
    e: np.ndarray | None = None         # measured input (absolute)
    y: np.ndarray | None = None         # measured output (absolute)
    t: np.ndarray | None = None
    e0: float = 0.0
    pc0: float = 0.0
    oversample: int = 1
    elapsed: float = 0.0
    pb: object = None
    ambiguous: list = field(default_factory=list)   # sets of effects the record cannot tell apart
    corners: dict = field(default_factory=dict)     # baseline groups left at a bound (baseline.corners)
    unseen_limits: list = field(default_factory=list)  # saturation limits the fit part does not show

    @property
    def cause(self) -> str:
        return self.causes[0] if self.causes else "none"

    @property
    def effect_params(self) -> dict:
        """The named effects' parameters (report units; saturation limits
        relative to the model's rest output, see output.effect_params_abs)."""
        return self.extended.effect_params(self.pb.setup.fs_int, self.oversample)


def noise_estimate(y: np.ndarray, e: np.ndarray) -> float:
    """Sample-to-sample (white) noise sd of the output from second
    differences away from input changes (robust: MAD). Coloured noise has
    more variance than this; see Diagnosis.noise_floor_val."""
    d2 = y[2:] - 2 * y[1:-1] + y[:-2]
    near = np.zeros(y.size, bool)
    for k in signals.change_points(e):
        near[max(0, k - 2):k + 12] = True
    d2 = d2[~near[1:-1]]
    if d2.size < 20:
        d2 = y[2:] - 2 * y[1:-1] + y[:-2]
    return signals.mad_sd(d2) / math.sqrt(6.0)


def _floor(rec, pb, final) -> tuple[float, str]:
    """Noise floor of the validation NRMSE: the noise process's sd (its
    colour included) over the sd of the measured validation output. From
    the opening rest stretch when it is long enough to show the noise's
    colour (a direct measurement), else from the final model's residual
    (an upper bound: any model error left counts as noise)."""
    sy = float(np.std(pb.held_of(pb.y)))
    if rec.rest >= 200:
        v = float(noise.fit(rec.pc[:rec.rest]).var)
        return math.sqrt(v) / sy, f"the opening rest stretch ({rec.rest} samples)"
    r = pb.fit_of(final.residual(pb))
    return float(np.std(r)) / sy, ("the final model's residual (an upper bound: model "
                                   "error left counts as noise)")


def _held_blocks_note(split, nm) -> list:
    """A held-out block shorter than holdout.CORR_TIMES of the noise's
    correlation times: its edges' noise correlates with the fit parts' beside
    them, and the held-out error may be optimistic."""
    tc = nm.correlation_time()
    h = min(b - a for a, b in split.held)
    if len(split.held) < 2 or holdout_mod.CORR_TIMES * tc <= h:
        return []
    return [f"The residual's noise stays correlated for {tc} samples, more than a "
            f"twentieth of the shortest held-out block ({h} samples): the held-out "
            "error may be optimistic (--holdout tail holds out one block)."]


def diagnose(rec, config: str, fixes: dict | None = None, *, order: int = 8,
             oversample: int | None = None, jobs: int | None = None, progress: bool = True,
             seed: int = 0, holdout: str = holdout_mod.DEFAULT) -> Diagnosis:
    t0 = time.monotonic()
    say = Progress(progress)
    if seed < 0:
        raise ValueError("seed must be a non-negative integer")
    m = data.check_cost(rec.n, rec.fs, oversample, rec.source)   # the API's too
    split, why = data.split_for(rec, holdout)
    if why:
        rec.notes.append(why)
    pb = Problem.from_record(rec, config, fixes, order, m, split)
    pb.user_fixed = dict(fixes or {})
    notes_nm = _noise_from_rest(rec, pb)
    if jobs is None:
        jobs = min(2, os.cpu_count() or 1)
    fit.set_threads(jobs)
    rng = np.random.default_rng(seed)
    say(f"{rec.n} samples at {rec.fs:g} Hz, config {config}; {split.describe(rec.fs)}; "
        f"simulated at {m}x")
    weighted = pb.nm is not None
    base, identified, reasons, fit_notes, nm0 = base_mod.fit_baseline(pb, rng, say)
    if not (weighted and pb.nm is None):     # else the baseline's note says why it is not
        fit_notes[:0] = notes_nm
    say(f"baseline: NRMSE fit {base.nrmse_fit:.4f}, validation {base.nrmse_val:.4f}, "
        f"noise {nm0.describe()}")
    ambiguous, sets = [], []
    final, pbf, rounds, checks = selection.forward(pb, base, seed * 1000 + 17, jobs, say,
                                                   ambiguous, sets)
    fit.settle(final, pbf)      # the intervals of the model reported (fit.uncertainty_later)
    base = _best_baseline(pb, base, rounds, fit_notes)
    fit.settle(base, pb, noise.fit)     # the baseline's, as baseline.prune makes them
    identified, corners = base_mod.report_corners(pb, base, identified)
    causes = _ordered(final, checks)
    sd = noise_estimate(pb.y, pb.e_abs)
    floor, src = _floor(rec, pb, final)
    nmf = noise.fit(pbf.fit_pieces(final.residual(pbf)))
    fit_notes += _held_blocks_note(split, nmf)
    fit_notes += candidates.corner_notes(rounds, causes)
    unseen = candidates.unseen_limits(pbf, final) if "saturation" in causes else []
    fit_notes += candidates.limit_notes(pbf, unseen)
    evb = ev_mod.analyse(pb, base, sd)
    eva = ev_mod.analyse(pbf, final, sd)
    evidence = ev_mod.describe(evb, pb, sd, floor, base)
    tests = rounds[0] if rounds else []
    why = ev_mod.verdict(causes, base, final, tests, checks, evb, eva, pbf, floor,
                         ambiguous)
    say("causes: " + (", ".join(causes) if causes else "none"))
    d = Diagnosis(config, rec.fs, rec.n, split, base, final, causes, tests, rounds, checks,
                  identified, reasons, evidence, why, evb, eva, sd, nmf, floor, src,
                  list(rec.notes), fit_notes, pb.e_abs, pb.y, rec.t,
                  float(final.e0), float(final.values["pc0"]), m, pb=pbf)
    d.ambiguous = sets
    d.corners = corners
    d.unseen_limits = unseen
    d.elapsed = time.monotonic() - t0
    return d


# Samples of opening rest from which the noise itself is measured.
MIN_NOISE_REST = 200


def _noise_from_rest(rec, pb) -> list:
    """With an opening rest stretch of MIN_NOISE_REST samples or more, the
    output there is the sensor noise alone: its AR model (noise.fit) is the
    record's noise model. Every fit then minimises the residual whitened by
    it (the output's likelihood under that noise), and the guards compare
    models under it. Without one, the fits are plain output error and each
    comparison whitens with the extended model's residual."""
    rest = min(rec.rest, pb.split.first_end)     # no held-out output reaches the fit
    if rest < MIN_NOISE_REST:
        return []
    nm = noise.fit(rec.pc[:rest])
    if nm.order == 0:
        return [f"The noise, measured on the opening {rest} samples at rest, is white."]
    pb.nm = nm
    return [f"The noise, measured on the opening {rest} samples at rest, is "
            f"{nm.describe()}: every fit minimises the residual whitened by it (the "
            "output's likelihood under that noise), and the guards compare models under it "
            "unless the residual of the model with the effect holds significantly less slow "
            f"noise than it claims (its long-run variance below the rest model's by more than "
            f"{guards.LONG_RUN_Z:.2f} standard errors; then under that residual's own: "
            "guards.noise_for)."]


def _best_baseline(pb, base, rounds, notes):
    """A reference refitted in round 1 with the baseline's own freedoms may
    have found a better optimum of the linear model (starting from an
    extended fit's groups): then that is the baseline. Compared on the
    baseline's own samples (selection.best_same_fit: a dead band's
    reference counts fewer, and fewer samples cost less whatever the fit)."""
    same = [t for t in (rounds[0] if rounds else []) if t.ref.free_groups == base.free_groups]
    best, _, src = selection.best_same_fit(same, base, pb)
    if best is not base:
        notes.append(f"The multi-start baseline was not the best optimum of the linear model: "
                     f"refitted from the {src} candidate's groups it fits better (RSS "
                     f"{base.cost:.4g} -> {best.cost:.4g}); that optimum is the baseline.")
    return best


def _ordered(final, checks) -> list:
    """Named effects, most important first (largest loss of fit when removed)."""
    by = {t.effect: t for t in checks}
    return sorted(final.effects, key=lambda e: by[e].dbic if e in by else 0.0)
