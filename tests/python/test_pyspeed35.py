# SPDX-License-Identifier: MIT
"""The Python around the simulations, made cheaper with the same numbers
(branch pyspeed35): each shortcut must give what the long way gives, bit
for bit, and must not hand out an answer for another input."""
import numpy as np
import pytest

from pneufrac_fit import fit, holdout, lib, model
from test_converge import _problem, _start     # the same small lag record


def test_the_input_shifted_by_e0_is_kept_per_record_length_and_e0_bits():
    """fit._input is e_abs[:n] - e0, read only; the same object again for
    the same record, n and e0; another array for another e0, another n,
    another record, and for -0.0 against 0.0 (the differences' zeros carry
    the sign)."""
    e = np.array([0.0, -0.0, 1.5, -2.25, 3.0])
    a = fit._input(e, None, 0.5)
    assert np.array_equal(a, e - 0.5) and not a.flags.writeable
    assert fit._input(e, None, 0.5) is a
    b = fit._input(e, 3, 0.5)
    assert b is not a and np.array_equal(b, e[:3] - 0.5)
    assert fit._input(e, None, 0.25) is not a
    z, mz = fit._input(e, None, 0.0), fit._input(e, None, -0.0)
    assert z is not mz
    assert np.array_equal(np.signbit(z), np.signbit(e - 0.0))
    assert np.array_equal(np.signbit(mz), np.signbit(e - (-0.0)))
    other = e.copy()
    assert fit._input(other, None, 0.5) is not a


def test_the_held_input_is_np_repeat_and_kept_only_when_read_only():
    """model.held_input is np.repeat(e, m); a read-only e's hold is kept
    and given again, a writable e is held afresh every time (it could
    change), and m = 1 is e itself."""
    e = np.arange(5.0) - 2.0
    h = model.held_input(e, 3)
    assert np.array_equal(h, np.repeat(e, 3))
    e[0] = 7.0                                   # a writable input changes...
    assert np.array_equal(model.held_input(e, 3), np.repeat(e, 3))   # ...and is seen
    r = e.copy()
    r.flags.writeable = False
    k = model.held_input(r, 2)
    assert np.array_equal(k, np.repeat(r, 2)) and not k.flags.writeable
    assert model.held_input(r, 2) is k
    assert model.held_input(r, 4) is not k
    assert model.held_input(r, 1) is r


def test_a_simulation_through_the_kept_inputs_is_the_same_numbers():
    """simulate_raw (kept shifted input, kept hold) gives the library's
    output for np.repeat(e_abs - e0, m), as the setup's run of a fresh
    writable copy does, at two e0 and at the first e0 again."""
    pb = _problem()
    if "e0" in pb.fixed:             # the record opens at rest: e0 fitted here
        del pb.fixed["e0"]
        pb.free.append("e0")
    vals = _start(pb, lag=0.01)
    for e0 in (vals["e0"], vals["e0"] + 1e-3, vals["e0"]):
        v = dict(vals, e0=e0)
        got = fit.simulate_raw(pb, ("lag",), v)
        g = fit._groups(pb, v)
        assert g["e0"] == e0
        fresh = pb.setup.simulate(g, pb.e_abs.copy() - e0, ("lag",), {**v, "dead": 0})
        assert np.array_equal(got, fresh)


def test_the_fit_parts_kept_per_split_are_the_splits_own():
    """Problem.fit_parts and nsim (kept per split and burn) are what the
    split says, for every burn and after the split changes, and a caller
    that edits the list it got does not edit the next caller's."""
    pb = _problem()
    for burn in (0, 30, 500):
        pb.burn = burn
        assert pb.fit_parts == pb.split.fit_slices(burn)
        assert pb.nsim == pb.split.end
    pb.split = holdout.Split(pb.split.n, ((1000, 1500),))
    assert pb.fit_parts == pb.split.fit_slices(pb.burn)
    assert pb.nsim == pb.split.end
    got = pb.fit_parts
    got.append(slice(0, 1))
    assert pb.fit_parts == pb.split.fit_slices(pb.burn)


def test_a_controller_filled_through_the_kept_field_types_runs_the_same():
    """The binding's fill (field types kept per struct class) sets what it
    is given: the same output as the defaults changed one field at a time
    would give; an unknown name and a fractional int are still refused."""
    p = lib.default_params("pid")
    e = np.r_[np.zeros(5), np.ones(200)]
    a = lib.Controller("pid", p, {"lag": 0.01, "saturate": 1, "sat_lo": -1.0,
                                  "sat_hi": 2.0}, 2000.0, order=6, t_slow=1.0).run(e)
    b = lib.Controller("pid", dict(p), {"saturate": 1.0, "sat_hi": 2.0, "sat_lo": -1.0,
                                        "lag": 0.01}, 2000.0, order=6, t_slow=1.0).run(e)
    assert np.array_equal(a, b) and np.all(np.isfinite(a)) and np.ptp(a) > 0
    c = lib.Controller("pid", p, {"lag": 0.02}, 2000.0, order=6, t_slow=1.0).run(e)
    assert not np.array_equal(a, c)
    with pytest.raises(KeyError):
        lib.Controller("pid", p, {"no_such_effect": 1.0}, 2000.0)
    with pytest.raises(ValueError):
        lib.Controller("pid", p, {"saturate": 1.5}, 2000.0)
    assert lib.config_id("pid") == lib.config_id("pid")
    with pytest.raises(KeyError):
        lib.config_id("no_such_config")
    with pytest.raises(KeyError):          # refused again, not kept
        lib.config_id("no_such_config")
