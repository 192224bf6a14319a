# SPDX-License-Identifier: MIT
"""The ctypes mirror matches the C headers, and the binding is the model."""
import ctypes
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from pneufrac_fit import lib, model

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_mirror_offsets_match_headers(tmp_path):
    src = tmp_path / "off.c"
    src.write_text("""
#include <stdio.h>
#include <stddef.h>
#include "pneufrac/pneufrac.h"
int main(void) {
  printf("%zu %zu %zu %zu\\n", sizeof(pf_params), sizeof(pf_effects), sizeof(pf_design_opts),
         offsetof(pf_ctrl_design, rt));
  printf("%zu %zu %zu %zu\\n", offsetof(pf_params, RCi), offsetof(pf_effects, lag),
         offsetof(pf_effects, saturate), offsetof(pf_design_opts, input));
  printf("%zu %zu\\n", sizeof(pf_ctrl_design), sizeof(pf_ctrl_f64));
  return 0;
}
""")
    exe = tmp_path / "off"
    subprocess.run(["cc", "-std=c99", "-I", str(ROOT / "lib" / "include"), str(src), "-o",
                    str(exe)], check=True)
    a, b, c = [list(map(int, ln.split())) for ln in
               subprocess.run([str(exe)], capture_output=True, text=True).stdout.splitlines()]
    assert a == [ctypes.sizeof(lib.Params), ctypes.sizeof(lib.Effects),
                 ctypes.sizeof(lib.DesignOpts), lib.RT_OFFSET]
    assert b == [lib.Params.RCi.offset, lib.Effects.lag.offset, lib.Effects.saturate.offset,
                 lib.DesignOpts.input.offset]
    assert c[0] <= lib.DESIGN_BYTES and c[1] <= lib.INSTANCE_BYTES


def test_groups_round_trip():
    for cfg in ("p", "dd", "id", "pid"):
        g = model.nominal_groups(cfg)
        p = model.physical_from_groups(cfg, g)
        g2 = model.groups_from_physical(cfg, dict(lib.default_params(cfg), **p))
        for k in g:
            assert abs(g2[k] / g[k] - 1) < 1e-12 if g[k] else g2[k] == 0


def test_group_mapping_reproduces_paper_output():
    """Only the groups matter: the paper's parameters and the fit's mapping of
    their groups give the same simulated output (k1*k2 split differently)."""
    e = np.repeat(np.random.default_rng(0).uniform(-1, 1, 20), 100)
    for cfg in ("p", "dd", "id"):
        p = lib.default_params(cfg)
        y0 = lib.simulate(cfg, p, {}, 1000.0, e)
        y1 = lib.Controller(cfg, model.physical_from_groups(cfg, model.nominal_groups(cfg)),
                            {}, 1000.0).run(e)
        assert np.max(np.abs(y1 - y0)) <= 1e-9 * np.max(np.abs(y0))


def test_library_refusal_names_parameter():
    p = lib.default_params("dd")
    p["beta"] = 1.5
    with pytest.raises(lib.ModelError) as ex:
        lib.Controller("dd", p, {}, 1000.0)
    assert ex.value.param == "beta"
