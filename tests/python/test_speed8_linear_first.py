# SPDX-License-Identifier: MIT
"""Saturation's loop solve skipped where no limit binds (issue 8, item 8;
branch speed8). With the supply limits the only effect inside the loop, the
loop equation is linear wherever p_c stays inside them, so the linear
solution, where its p_c is inside, is the root; the double runtime now
takes it there instead of polishing it with the loop solve's Newton steps
(pf_ctrl_float.inc, PF_LINEAR_FIRST). A saturation simulation then costs
about what one without it costs (8.6 -> 6.4 ms for 70 000 samples of pid at
2x on the 2-core machine).

What it must keep: a run whose limits never bind is the run without
saturation, bit for bit (before, the solve moved each sample's root by
rounding, so the two differed in the last digits), and a run whose limits
bind still clips (the solve runs on those samples)."""
import numpy as np
import pytest

from pneufrac import binding
from pneufrac_fit import model

FS = 2000.0


def _input(n=6000, seed=5):
    rng = np.random.default_rng(seed)
    return np.repeat(rng.uniform(-0.4, 0.4, n // 300 + 1), 300)[:n] + 0.01 * rng.standard_normal(n)


def _run(config, fx, e):
    p = model.physical_from_groups(config, model.nominal_groups(config))
    c = binding.Controller(config, p, fx, FS, order=8, t_slow=10.0)
    return c.run(e), c.limited


@pytest.mark.parametrize("config", ["p", "dd", "id", "pid"])
@pytest.mark.parametrize("kind", [model.SAT_CLIP, model.SAT_STOP, model.SAT_WIND])
def test_limits_that_never_bind_are_the_model_without_them(config, kind):
    e = _input()
    free, _ = _run(config, {}, e)
    span = float(free.max() - free.min())
    far = {"saturate": kind, "sat_lo": float(free.min()) - span, "sat_hi": float(free.max()) + span}
    out, limited = _run(config, far, e)
    assert limited == 0
    assert np.array_equal(out, free)


@pytest.mark.parametrize("config", ["p", "dd", "id", "pid"])
def test_limits_that_bind_still_clip(config):
    """The output still clips where the limits bind. This cannot tell
    whether the loop solve ran on those samples (the final clip and the
    count of limited samples happen whatever x is): the C test
    test_effects' lever check (x = ce e - cy y on every sample, every
    placement) is what fails if the solve were skipped where it binds."""
    e = _input()
    free, _ = _run(config, {}, e)
    lo, hi = float(free.min()), float(free.max())
    lim = {"saturate": model.SAT_CLIP, "sat_lo": lo + 0.25 * (hi - lo), "sat_hi": hi - 0.25 * (hi - lo)}
    out, limited = _run(config, lim, e)
    assert limited > 0
    assert out.max() <= lim["sat_hi"] * (1 + 1e-12) + 1e-12
    assert out.min() >= lim["sat_lo"] * (1 + 1e-12) - 1e-12
    inside = (free > lim["sat_lo"]) & (free < lim["sat_hi"])
    assert not np.array_equal(out[~inside], free[~inside])
