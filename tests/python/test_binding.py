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


MIRRORS = [("pf_params", lib.Params), ("pf_effects", lib.Effects),
           ("pf_design_opts", lib.DesignOpts), ("pf_ctrl_design", lib.DesignHead)]


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_mirror_offsets_match_headers(tmp_path):
    """sizeof and offsetof of every mirrored field, from the C compiler."""
    lines = []
    for cname, cls in MIRRORS:
        for fname, _ in cls._fields_:
            lines.append(f'  printf("{cname}.{fname} %zu %zu\\n", offsetof({cname}, {fname}), '
                         f'sizeof((({cname} *)0)->{fname}));')
        if cname != "pf_ctrl_design":
            lines.append(f'  printf("{cname}.sizeof %zu\\n", sizeof({cname}));')
    src = tmp_path / "off.c"
    src.write_text("""
#include <stdio.h>
#include <stddef.h>
#include "pneufrac/pneufrac.h"
int main(void) {
%s
  printf("pf_ctrl_design.rt %%zu\\n", offsetof(pf_ctrl_design, rt));
  printf("sizes %%zu %%zu\\n", sizeof(pf_ctrl_design), sizeof(pf_ctrl_f64));
  return 0;
}
""" % "\n".join(lines))
    exe = tmp_path / "off"
    subprocess.run(["cc", "-std=c99", "-I", str(ROOT / "lib" / "include"), str(src), "-o",
                    str(exe)], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    got = {ln.split()[0]: [int(x) for x in ln.split()[1:]] for ln in out.splitlines()}
    want = {}
    for cname, cls in MIRRORS:
        for fname, ctype in cls._fields_:
            want[f"{cname}.{fname}"] = [getattr(cls, fname).offset, ctypes.sizeof(ctype)]
        if cname != "pf_ctrl_design":
            want[f"{cname}.sizeof"] = [ctypes.sizeof(cls)]
    mismatch = {k: (got.get(k), v) for k, v in want.items() if got.get(k) != v}
    assert not mismatch, f"C (offset, size) vs ctypes: {mismatch}"
    n_fields = sum(len(cls._fields_) for _, cls in MIRRORS)
    assert n_fields >= 33                       # every field, not a sample
    assert got["pf_ctrl_design.rt"] == [lib.RT_OFFSET]
    design, instance = got["sizes"]
    assert design == lib.DESIGN_BYTES and instance == lib.INSTANCE_BYTES


def test_check_layout_reads_back_every_field():
    """The run-time self-check sees every field: a request with a distinct
    value per field round-trips through the library's design."""
    import ctypes as C
    l = lib.load()
    p, fx, o = lib._layout_request(l)
    assert len({getattr(p, n) for n, _ in lib.Params._fields_[1:]}) >= 15
    buf = C.create_string_buffer(lib.DESIGN_BYTES)
    assert l.pf_ctrl_design_make(buf, C.byref(p), C.byref(fx), C.byref(o)) == 0
    d = lib.DesignHead.from_buffer(buf)
    for part, req in (("p", p), ("fx", fx), ("opt", o)):
        for n, _ in type(req)._fields_:
            assert getattr(getattr(d, part), n) == getattr(req, n), f"{part}.{n}"


def test_layout_checked_before_caching(monkeypatch):
    """A library that fails the self-check is not cached as loaded."""
    monkeypatch.setattr(lib, "_lib", None)

    def boom(_l):
        raise lib.LibraryError("mismatch")
    monkeypatch.setattr(lib, "check_layout", boom)
    with pytest.raises(lib.LibraryError):
        lib.load()
    assert lib._lib is None
    with pytest.raises(lib.LibraryError):   # and the next call checks again
        lib.load()


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


def _refuse_in_worker(_):
    p = lib.default_params("dd")
    p["beta"] = 1.5
    lib.Controller("dd", p, {}, 1000.0)


def test_refusal_in_a_worker_process_reaches_the_parent():
    """A diagnosis runs its rounds in a process pool: a refusal raised in a
    worker must arrive in the parent, status and parameter included (an
    exception the parent cannot unpickle leaves the pool waiting for ever)."""
    import multiprocessing as mp
    with mp.get_context("fork").Pool(1) as pool:
        res = pool.map_async(_refuse_in_worker, [0])
        with pytest.raises(lib.ModelError) as ex:
            res.get(timeout=60)
    assert ex.value.param == "beta" and ex.value.status != 0
    assert "beta" in str(ex.value)


@pytest.mark.parametrize("kind", [1.5, 2.5, True, "2", float("nan"), float("inf")])
def test_whole_number_fields_are_not_truncated(kind):
    """An int field (here the saturation's placement) given a value that is
    not a whole number is refused, not truncated to another placement."""
    fx = {"saturate": kind, "sat_lo": -0.5, "sat_hi": 0.5}
    with pytest.raises(ValueError, match="saturate.*whole number"):
        lib.Controller("pid", lib.default_params("pid"), fx, 1000.0)


def test_whole_number_fields_take_whole_floats():
    fx = {"saturate": 2.0, "sat_lo": -0.5, "sat_hi": 0.5}
    y = lib.Controller("pid", lib.default_params("pid"), fx, 1000.0).run(np.ones(50))
    assert np.max(y) <= 0.5 + 1e-12


def test_ranges_come_from_the_library():
    """model.py and the binding read names, ranges and uses from the C table."""
    r = lib.param_range("beta")
    assert (r.lo, r.hi, r.lo_open, r.hi_open) == (0.0, 1.0, True, False)
    assert 0.0 not in r and 1.0 in r and 1.0000001 not in r
    assert r.desc and r.unit == ""
    assert lib.param_range("tau").unit == "s"
    assert model.group_bounds("q") == (0.0, 1.0)
    assert model.group_bounds("beta") == (0.05, 1.0)
    assert model.group_bounds("tau") == (None, None)
    with pytest.raises(KeyError):
        lib.param_range("gamma")
    for cfg in ("p", "dd", "id", "pid"):
        for name in ("nu", "w", "RC", "RCd"):
            assert lib.param_used(cfg, name) == (name in model.CONFIG_GROUPS[cfg])


def test_library_not_found_names_where_it_looked(monkeypatch):
    """With no library in any searched place the message names the places
    searched (it read "tried: nothing", which tells the user nothing)."""
    from pneufrac import binding, locate
    monkeypatch.setattr(binding, "_lib", None)
    monkeypatch.setattr(locate, "candidates", lambda: iter(()))
    with pytest.raises(binding.LibraryError) as exc:
        binding.load()
    text = str(exc.value)
    assert "searched" in text and "pkg-config" in text and "nothing" not in text
    assert all(d in text for d in ("build/lib", "lib64"))
    assert binding._lib is None
