# SPDX-License-Identifier: MIT
"""Shrink a hidden effect until it disappears; report where detection stops.

At every size the verdict must be the true cause or 'none' (never a wrong
cause); the largest size must be found and the smallest, far below the
noise, must be reported as 'none'. Run with -s to see the table."""
import pytest

import cases

SERIES = {
    # effect: (config, size in [0, 1] of the drawn range, scales)
    "dead_time": ("dd", 0.0, [1.0, 0.5, 0.3, 0.1]),        # 3 samples down to 0.3
    "backlash": ("dd", 0.0, [1.0, 0.3, 0.1, 0.03, 0.01]),  # 1 % of span down to 0.01 %
    "lag": ("p", 0.0, [1.0, 0.3, 0.1, 0.03]),              # 4 samples down to 0.12
}


@pytest.mark.parametrize("effect", list(SERIES))
def test_shrinking_effect(effect, capsys):
    config, size, scales = SERIES[effect]
    rows = []
    for s in scales:
        ds = cases.make(config, effect, 500, size=size, scale=s)
        d = cases.run(ds, jobs=2)
        rows.append((s, ds.effect_params, d.cause, d.baseline.nrmse_val,
                     d.extended.nrmse_val, ds.noise_floor))
    with capsys.disabled():
        print(f"\n{effect} on {config}: where detection stops (noise {cases.NOISE:.1%} of span)")
        for s, ep, cause, b, a, f in rows:
            desc = ", ".join(f"{k}={v:.4g}" for k, v in ep.items())
            print(f"  scale {s:5.2f}  {desc:36s} verdict {cause:10s} "
                  f"val NRMSE {b:.4f} -> {a:.4f} (floor {f:.4f})")
    causes = [r[2] for r in rows]
    assert all(c in (effect, "none") for c in causes), causes
    assert causes[0] == effect, causes
    assert causes[-1] == "none", causes
