# SPDX-License-Identifier: MIT
"""Saturation at its three places (the library's saturate, pf_effects.h):
p_c clipped after the relay, the relay's diaphragm on its seat, or the
relay's output stopped while its memory winds on. A record made with one
is named `saturation` with that placement when the record tells it from
the others, and the report says which; a placement the record does not
tell is said to be so, never claimed."""
import numpy as np
import pytest

import cases
from pneufrac_fit import evidence, excite, generate, model


def _record(kind: int, seed: int):
    """cases.make's dd record with saturation, the limits acting at `kind`."""
    rng = np.random.default_rng(seed)
    params = generate.perturbed_params("dd", rng)
    e = excite.make("steps", cases.N, cases.FS, rng, rest=0.1)
    ev = dict(cases.sizes("saturation", rng, e, "dd", params), sat_kind=kind)
    return generate.generate("dd", effects={"saturation": ev}, n=cases.N, fs=cases.FS,
                             noise=cases.NOISE, seed=seed + 7, e=e, params=params,
                             **cases.PLANT)


@pytest.mark.parametrize("kind", [model.SAT_CLIP, model.SAT_STOP, model.SAT_WIND])
def test_the_placement_is_fitted_and_reported(kind):
    ds = _record(kind, 11)
    d = cases.run(ds)
    assert d.causes == ["saturation"], cases.explain(ds, d)
    p = d.effect_params
    span = float(np.ptp(ds.pc))
    for k in ("sat_lo", "sat_hi"):
        assert abs(p[k] - ds.effects["saturation"][k]) <= cases.SAT_TOL * span
    # After every saturated stretch the clip's output stays at the limit
    # while its relay's memory winds back (13 ms on Example 6 at 20 kHz,
    # test_relay_stop), the wound-on relay's longer (85 ms) and the seated
    # relay's follows the input: with several saturated steps at 0.5 %
    # noise the record tells them apart
    assert p["sat_kind_told"] == 1.0 and p["sat_kind"] == kind
    line = evidence.describe_effect("saturation", p, ds.fs)
    assert model.SAT_KINDS[kind] in line and "does not tell" not in line
    p["sat_kind_told"] = 0.0       # and the words for a record that does not
    assert "does not tell" in evidence.describe_effect("saturation", p, ds.fs)
