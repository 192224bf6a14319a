# SPDX-License-Identifier: MIT
"""When an effect may be named: the guards.

An effect is tested as a model WITH it against a reference WITHOUT it that
has exactly the same freedoms (every group the extended fit frees is freed
in the reference too, and the reference is refitted from both its own
optimum and the extended model's, so that a gain which came from groups
moving to another optimum is credited to those groups, not to the effect).
It is named only when all of these hold:

1. Significant. The 95 % interval of its size excludes the no-effect value
   (sandwich covariance under the noise model: it holds for coloured noise).
2. Material. Its contribution to the output, the extended model against the
   same model with the effect switched off, reaches MATERIAL_SIGMAS times the
   noise sd somewhere on the record, and its energy is MATERIAL_SNR times the
   noise's (whitened): a change the eye could not see in the data, or one
   that only a long record makes significant, is no reason to take a
   controller apart. Timing effects (dead time, line lag) must also last at
   least half a sample: shorter ones cannot be told from the sampling
   instants of e and pc, the converters' own timing and the model's
   discretisation.
3. Earns its place. Against the same-freedom reference: BIC (on the
   residuals whitened by the extended model's noise model, the same filter
   for both) lower by more than MIN_DBIC, and the held-out whitened mean-
   square error lower by more than MIN_VAL_GAIN.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import fit, model, noise

Z95 = 1.959963984540054
MIN_DBIC = 10.0              # "very strong" on Kass & Raftery's scale
MIN_VAL_GAIN = 0.05
MATERIAL_SIGMAS = 1.0        # peak contribution, noise sd
MATERIAL_SNR = 100.0         # whitened energy of the contribution, noise variances
MIN_TIMING = 0.5             # samples
APPROX_RATIO = 4.0           # contribution energy over the model's discretisation error
APPROX_FINER = 8
TIMING_RATIO = 1.0           # contribution energy over the input-timing error's expected energy


@dataclass
class Test:
    effect: str
    model: object                # FitResult with the effect
    ref: object                  # FitResult without it, same freedoms
    dbic: float = math.nan
    lr: float = math.nan          # whitened likelihood ratio against the reference
    val_gain: float = math.nan
    interval: tuple = (None, None)
    excludes: bool = False
    peak: float = 0.0            # peak |contribution| / noise sd
    snr: float = 0.0             # whitened energy / innovation variance
    approx: float = math.inf     # energy / energy of the model's discretisation error
    timing: float = math.inf     # energy / expected energy of the input-timing error
    timing_ok: bool = True
    passes: bool = False
    reasons: list = field(default_factory=list)    # why it fails, in words
    nm: object = None

    @property
    def significant(self) -> bool:
        return self.excludes

    @property
    def material(self) -> bool:
        return (self.peak >= MATERIAL_SIGMAS and self.snr >= MATERIAL_SNR and self.timing_ok
                and self.approx >= APPROX_RATIO and self.timing >= TIMING_RATIO)


def _switched_off(pb, fr, effect):
    """The model's output with one effect off, everything else as fitted."""
    rest = tuple(x for x in fr.effects if x != effect)
    v = dict(fr.values)
    dead = 0 if effect == "dead_time" else fr.dead
    if fr.K_solved:
        v["K"] = 1.0
        return fr.values["K"] * fit.simulate_raw(pb, rest, v, dead) + fr.values["pc0"]
    return fit.simulate_raw(pb, rest, v, dead) + fr.values["pc0"]


def approximation_error(pb, fr) -> np.ndarray:
    """The model's own discretisation error at fr's parameters: its output
    as simulated, minus the same model simulated APPROX_FINER times finer
    (the error falls about as the step: this is most of it)."""
    m = pb.setup.oversample * APPROX_FINER
    return fr.sim - (_scaled_sim(pb, fr, fr.effects, fr.dead, m) + fr.values["pc0"])


def _scaled_sim(pb, fr, effects, dead, m):
    v = dict(fr.values)
    if fr.K_solved:
        v["K"] = 1.0
        return fr.values["K"] * fit.simulate_raw(pb, effects, v, dead, None, m)
    return fit.simulate_raw(pb, effects, v, dead, None, m)


def input_timing_error(pb, fr) -> np.ndarray:
    """How much the model's output depends on when, within a data sample,
    the input changed: the sampled input does not say (an input that moves
    between samples, a converter's own timing), and the model holds each
    sample over the next period. A change uniformly anywhere in the period
    is late by half a sample on average, which the fitted dynamics absorb,
    and scattered about that by sd 1/sqrt(12) sample, which they cannot:
    the output with the input half a sample late, minus as simulated, scaled
    to that sd (to first order the error grows in proportion to the shift)."""
    m = 2 * pb.setup.oversample
    effects = model.canonical(tuple(fr.effects) + ("dead_time",))
    # dead time in samples of pb's simulation rate, scaled to m's: half a
    # data sample is a whole number of samples at twice the rate
    late = _scaled_sim(pb, fr, effects, fr.dead + 0.5 * pb.setup.oversample, m)
    return (fr.sim - (late + fr.values["pc0"])) * (2.0 / math.sqrt(12.0))


def _interval(pb, fr, effect, contrib_range):
    """(lo, hi) of the effect's size in natural units and whether it
    excludes the no-effect value; dead time is tested by the likelihood
    ratio against the reference instead (its size is a whole number)."""
    if effect == "dead_time":
        return (None, None), None
    if effect == "saturation":
        out = []
        ok = False
        smin, smax = contrib_range
        for name, edge, inside in (("sat_lo", smin, 1), ("sat_hi", smax, -1)):
            v, s = fr.values[name], fr.se.get(name, math.inf)
            lo, hi = v - Z95 * s, v + Z95 * s
            out.append((lo, hi))
            # the limit clips only if it lies inside the range the
            # unclipped output reaches
            if math.isfinite(s) and ((inside > 0 and lo > edge) or (inside < 0 and hi < edge)):
                ok = True
        return tuple(out), ok
    name = {"lag": "lag", "backlash": "deadband", "nozzle": "nozzle_k"}[effect]
    v, s = fr.values[name], fr.se.get(name, math.inf)
    if fit.transform_of(name) == "log":
        s = v * s                      # delta method: natural units
    lo, hi = v - Z95 * s, v + Z95 * s
    return (lo, hi), bool(math.isfinite(s) and lo > 0)


def test(pb, effect: str, fr, ref, pb_ref=None) -> Test:
    """Guards for `effect` in model fr against the same-freedom reference."""
    pb_ref = pb_ref or pb
    t = Test(effect, fr, ref)
    sl = pb.counted
    n = pb.nfit
    r1 = fr.residual(pb)
    r0 = ref.residual(pb_ref)
    # the record's noise model when it was measured at rest, else the
    # extended model's residual's (under "no effect" both residuals agree;
    # under "effect" that residual is the noise)
    nm = pb.nm if pb.nm is not None else noise.fit(r1[sl])
    t.nm = nm
    w1, w0 = nm.whiten(r1[sl]), nm.whiten(r0[sl])
    m = w1.size
    rss1, rss0 = float(w1 @ w1), float(w0 @ w0)
    t.dbic = m * math.log(max(rss1, 1e-300) / max(rss0, 1e-300)) + (fr.k - ref.k) * math.log(m)
    # Held-out gain, as measured and whitened: the smaller counts. Whitening
    # weighs the fast part of the error (where a coloured noise is weak);
    # an effect that only helps there, and not in the error as measured, is
    # fitting the model's own discretisation at the input's fast changes.
    v1, v0 = nm.whiten(r1[n:]), nm.whiten(r0[n:])
    mse1, mse0 = float(v1 @ v1), float(v0 @ v0)
    gw = 1.0 - mse1 / mse0 if mse0 > 0 else 0.0
    p1, p0 = r1[n:] - np.mean(r1[n:]), r0[n:] - np.mean(r0[n:])
    mp1, mp0 = float(p1 @ p1), float(p0 @ p0)
    gp = 1.0 - mp1 / mp0 if mp0 > 0 else 0.0
    t.val_gain = min(gw, gp)
    off = _switched_off(pb, fr, effect)
    d = fr.sim - ref.sim
    sd = math.sqrt(max(nm.var, 1e-300))
    t.peak = float(np.max(np.abs(d))) / sd
    dw = nm.whiten(d[sl] - np.mean(d[sl]))
    t.snr = float(dw @ dw) / max(nm.sigma2, 1e-300)
    a = approximation_error(pb_ref, ref)[sl]
    dc = d[sl] - np.mean(d[sl])
    t.approx = float(dc @ dc) / max(float(a @ a), 1e-300)
    b = input_timing_error(pb_ref, ref)[sl]
    t.timing = float(dc @ dc) / max(float(b @ b), 1e-300)
    fs = pb.setup.fs
    if effect == "lag":
        t.timing_ok = fr.values["lag"] * fs >= MIN_TIMING
    elif effect == "dead_time":
        t.timing_ok = fr.dead / pb.setup.oversample >= MIN_TIMING
    if effect == "saturation":
        t.interval, t.excludes = _interval(pb, fr, effect, (float(np.min(off[sl])),
                                                             float(np.max(off[sl]))))
    else:
        t.interval, _ = _interval(pb, fr, effect, None)
    # The profile-likelihood interval: the no-effect value (the reference
    # is the model refitted there) lies outside the 95 % interval when the
    # whitened likelihood ratio exceeds the chi-square(1) 95 % point.
    t.lr = m * math.log(max(rss0, 1e-300) / max(rss1, 1e-300))
    t.excludes = t.lr > Z95 ** 2
    if not t.excludes:
        t.reasons.append("its 95 % interval includes the no-effect value")
    if not t.timing_ok:
        t.reasons.append(f"it lasts under {MIN_TIMING:g} sample (below the record's time resolution)")
    if t.peak < MATERIAL_SIGMAS:
        t.reasons.append(f"its largest contribution to the output is {t.peak:.2g} noise sd "
                         f"(need {MATERIAL_SIGMAS:g})")
    if t.approx < APPROX_RATIO:
        t.reasons.append(f"its contribution's energy is {t.approx:.3g}x that of the model's own "
                         f"discretisation error (need {APPROX_RATIO:g}x)")
    if t.timing < TIMING_RATIO:
        t.reasons.append(f"its contribution's energy is {t.timing:.3g}x what the input's unknown "
                         f"timing within a sample makes (need {TIMING_RATIO:g}x)")
    if t.snr < MATERIAL_SNR:
        t.reasons.append(f"its contribution's energy is {t.snr:.3g} noise variances "
                         f"(need {MATERIAL_SNR:g})")
    if not t.dbic < -MIN_DBIC:
        t.reasons.append(f"BIC changes by {t.dbic:+.1f} against the same model without it "
                         f"(need < -{MIN_DBIC:g})")
    if not t.val_gain > MIN_VAL_GAIN:
        t.reasons.append(f"the held-out error falls by {100 * t.val_gain:.1f} % "
                         f"(need > {100 * MIN_VAL_GAIN:g} %)")
    t.passes = not t.reasons
    return t


def indistinguishable(a: Test, b: Test) -> bool:
    """Whether the record cannot tell two passing candidates apart, a the
    one with the lower held-out NRMSE. It tells them apart when a wins every
    comparison the guards make, the same way round: on the fit part by BIC
    (residuals whitened by a's noise model for both, over the samples both
    count, each model's own parameter count) lower by more than MIN_DBIC, and
    on the held-out part in the error as measured and whitened. When b is as
    good on the fit part, or better on either held-out measure, the evidence
    is missing or conflicts: the two explain the record equally well within
    the noise."""
    n = a.pb.nfit
    ra, rb = a.model.residual(a.pb), b.model.residual(b.pb)
    nm = a.nm
    k = max(a.pb.burn, b.pb.burn)
    fa, fb = nm.whiten(ra[k:n]), nm.whiten(rb[k:n])
    m = fa.size
    dbic = (m * math.log(max(float(fa @ fa), 1e-300) / max(float(fb @ fb), 1e-300))
            + (a.model.k - b.model.k) * math.log(max(m, 1)))
    va, vb = nm.whiten(ra[n:]), nm.whiten(rb[n:])
    pa, pb_ = ra[n:] - np.mean(ra[n:]), rb[n:] - np.mean(rb[n:])
    return not (dbic < -MIN_DBIC and float(va @ va) < float(vb @ vb)
                and float(pa @ pa) < float(pb_ @ pb_))
