# SPDX-License-Identifier: MIT
"""A baseline that does not collapse under a noise model that does not
describe its residual (baseline.weigh_or_not).

A clean dd record with a PRBS input and resonant AR(2) sensor noise that
opens with 0.4 s at rest: the noise measured there has innovations about a
tenth of its sd, so weighting the fit by it amplifies the model's own error
at the PRBS edges (the plant here is simulated at 10x the data rate with
another Oustaloup order) and lets slow errors cost almost nothing. Before
the rule the baseline went to a corner (rho at its bound of 1e4) with a
held-out NRMSE of 0.048 against a noise floor of 0.0155; plain output error
reaches 0.0163."""
import cases

# A clean record's linear fit reaches its noise: held-out NRMSE within this
# factor of the true floor (the record holds nothing the model lacks
# beyond its own discretisation).
NEAR_FLOOR = 1.5


def test_clean_prbs_under_resonant_noise_fits_to_the_noise():
    ds = cases.make("dd", "none", 1, input_kind="prbs", noise_kind="ar2", rest=0.4, n=6000)
    d = cases.run(ds)
    assert d.causes == [], cases.explain(ds, d)
    assert d.baseline.nrmse_val < NEAR_FLOOR * ds.noise_floor, cases.explain(ds, d)
    # the report says in words why the measured noise model was not used
    assert any("does not describe the baseline's residual" in s for s in d.fit_notes)
    assert d.pb.nm is None
