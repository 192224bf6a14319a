# SPDX-License-Identifier: MIT
"""A dead band shrunk from the smallest size of the hidden-effect range to
far below the noise: named at full size, none at the smallest, never a
wrong cause. The full series (three effects, white and AR(1) noise) is
bench/bench_fit.py limits (docs/analysis-bench.md)."""
import numpy as np

import cases
from pneufrac_fit import excite, generate


def test_shrinking_dead_band():
    rng = np.random.default_rng(500)
    params = generate.perturbed_params("dd", rng)
    e = excite.steps(cases.N, cases.FS, rng)
    db = generate.draw_effect("backlash", "dd", rng, cases.FS, e, 0.0, params)["deadband"]
    causes = []
    for scale in (1.0, 0.03):
        ds = generate.generate("dd", effects={"backlash": {"deadband": db * scale}},
                               n=cases.N, fs=cases.FS, noise=cases.NOISE, seed=507, e=e,
                               params=params, **cases.PLANT)
        causes.append(cases.run(ds).causes)
    assert causes == [["backlash"], []], causes
