# SPDX-License-Identifier: MIT
"""pneufrac-fit diagnose on records from the independent simulator
(tests/python/indepsim: another discretisation, effects placed physically,
a DAQ, coloured noise, ADC steps, non-step inputs; it shares no code with
the fitted model). The cases were chosen before any was run, to cover the
kinds of record (clean with coloured noise, drift, jitter, a sweep, an
input that never rests; each effect; an off-inflection nozzle; 10 kHz; two
effects at once) and the four configurations (by-seed recipes take seed
mod 4 as p, dd, id, pid); the seeds are not picked for passing. The full
catalogue over more seeds is bench/bench_diagnose_indep.py
(docs/analysis-indep.md).

Acceptance as in cases.check: exactly the true causes; dead time within 2
data samples, lag, dead band and x_1/2 within 25 % (or inside the reported,
informative 95 % interval); saturation limits within 5 % of the output's
range (a side that never clips has no true limit); the validation NRMSE at
least halfway from the baseline's to the true noise floor."""
import numpy as np
import pytest

import cases
from indepsim.make import make, true_floor_held
from pneufrac_fit import data, diagnose

CASES = [
    ("clean-pid-real", 1), ("clean-drift", 1), ("clean-never-rest", 1),
    ("clean-jitter", 1), ("clean-sweep", 2),
    ("dead_time-steps", 2), ("lag-steps", 3), ("saturation-steps", 0),
    ("backlash-real", 1), ("nozzle-offbias", 0), ("dead_time-10khz", 1),
    ("two-lag-backlash", 1),
]
# Cases whose one parameter the record does not determine within its
# tolerance, every other check holding: (scenario, seed) -> (the
# parameter, the relative error it must still be within). An entry
# excuses that shortfall only, and a fix that brings the parameter within
# the tolerance fails the test until the entry is removed. None now:
# two-lag-backlash-1 (both causes named, under 1/f noise; its lag came out
# +34 %, 38.4 ms against 28.6, with a 95 % interval of [7.7, 192] ms under
# the long-memory noise model: docs/analysis-bench.md, branch interval29)
# was excused until stop 36, whose search (Jacobians at half the rate on
# its way: fit.COARSE_DEVIANCE) recovered the lag within its tolerance.
SHORT_OF: dict = {}


def check(rec, d) -> list[str]:
    t = rec.truth
    truth = set(t["causes"])
    if set(d.causes) != truth:
        return [f"causes {d.causes or ['none']}, expected {sorted(truth) or ['none']}"]
    bad = []
    p = d.effect_params
    span = float(np.ptp(rec.pc))
    for eff in t["effects"]:
        name, tp = eff["cause"], eff["params"]
        if name == "dead_time":
            got, want = p["dead_time"] * t["record"]["fs"], tp["dead_time_samples"]
            if abs(got - want) > cases.DEAD_TOL:
                bad.append(f"dead time {got:g} samples, true {want:.2f}")
        elif name in cases.PARAM_KEY:
            k = cases.PARAM_KEY[name]
            if not (abs(p[k] / tp[k] - 1) <= cases.REL_TOL or cases.in_ci(d, k, tp[k])):
                bad.append(f"{k} {p[k]:.4g}, true {tp[k]:.4g}")
        elif name == "saturation":
            for k in ("sat_lo", "sat_hi"):
                if tp.get(k) is not None and not abs(p[k] - tp[k]) <= cases.SAT_TOL * span:
                    bad.append(f"{k} {p[k]:.4g}, true {tp[k]:.4g} (range {span:.4g})")
    if truth:
        bad += cases.not_halfway(d, true_floor_held(rec.pc, rec.noise, d.split.held, d.n,
                                                t["noise"]["noise_floor_val"]))
    return bad + cases.bound_faults(d)


@pytest.mark.parametrize("scenario,seed", CASES)
def test_independent_record(scenario, seed):
    rec = make(scenario, seed)
    r = data.make_record(rec.t, rec.e, rec.pc, f"{scenario}-{seed}")
    d = diagnose.diagnose(r, rec.truth["config"], jobs=2, progress=False)
    bad = check(rec, d)
    if (scenario, seed) in SHORT_OF:
        key, tol = SHORT_OF[scenario, seed]
        tp = next(e["params"][key] for e in rec.truth["effects"]
                  if cases.PARAM_KEY.get(e["cause"]) == key)
        err = abs(d.effect_params[key] / tp - 1)
        assert any(b.startswith(key + " ") for b in bad), \
            f"{scenario}-{seed}: {key} now recovered: remove it from SHORT_OF"
        assert err <= tol, f"{scenario}-{seed}: {key} off by {err:.0%}, more than {tol:.0%}"
        bad = [b for b in bad if not b.startswith(key + " ")]
    assert not bad, (f"{scenario}-{seed} ({rec.truth['config']}): " + "; ".join(bad)
                     + " | " + " ".join(d.why))
