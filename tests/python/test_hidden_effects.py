# SPDX-License-Identifier: MIT
"""Hide one effect in a synthetic bump test and require the diagnosis to
find it: the right cause, its parameter recovered, and the validation
NRMSE at least halfway from the baseline's to the noise floor. Clean data
must give 'none'. Sizes are drawn at random (seeded) within the ranges of
pneufrac_fit.generate.draw_effect; the plant's own parameters vary around
the paper's values (generate.perturbed_params)."""
import pytest

import cases

CONFIGS = ["p", "dd", "id"]
EFFECTS = ["none", "dead_time", "lag", "saturation", "backlash", "nozzle"]


@pytest.mark.parametrize("effect", EFFECTS)
@pytest.mark.parametrize("config", CONFIGS)
def test_hidden_effect_is_found(config, effect):
    seed = 100 + 10 * CONFIGS.index(config) + EFFECTS.index(effect)
    ds = cases.make(config, effect, seed)
    d = cases.run(ds, jobs=2)
    bad = cases.check(ds, d)
    assert not bad, (f"{config}/{effect} (seed {seed}, hidden {ds.effect_params}): "
                     + "; ".join(bad) + " | verdict: " + " ".join(d.why))
