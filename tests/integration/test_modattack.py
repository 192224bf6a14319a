# SPDX-License-Identifier: MIT
"""Attacks by an outside client (branch modattack, docs/pneufracd.md): what
they found, each kept as a test that failed before its fix."""

from pfd import REG, Raw, Regs, exception_code, f32, fc06, fc16, fc23


def test_int16_mirrors_keep_inputs_in_range(daemon):
    """e_i16, sp_i16 and pv_i16 write e = v * in_fs / 32768. in_fs goes up
    to 1e12, so before, e_i16 = 32767 set e to 1e12 (and the loop ran on
    it), past e's documented 1e9 that an f32 write of e is held to. Such a
    write is now refused with exception 03 and changes nothing, by FC06,
    FC16 and FC23; a mirror value inside the range still writes."""
    d = daemon()
    with d.client() as c:
        r = Regs(c)
        r.write("in_fs", 1e12)
        r.write("commit", 1)
        assert r.read("commit_result") == 0
        assert r.read("committed_in_fs") == f32(1e12)
        raw = Raw(d.port)
        try:
            for name in ("e_i16", "sp_i16", "pv_i16"):
                for v in (32767, -32768, 33, -33):
                    assert exception_code(raw.request(1, fc06(REG[name][1], v))) == 3, (name, v)
            assert exception_code(raw.request(1, fc16(REG["e_i16"][1], [1, 1, 32767]))) == 3
            assert exception_code(raw.request(1, fc23(REG["e"][1], 2, REG["e_i16"][1], [32767]))) == 3
            for name in ("e", "sp", "pv"):
                assert r.read(name) == 0.0, name
            # 32 * 1e12 / 32768 = 9.77e8: inside the range, written.
            assert exception_code(raw.request(1, fc06(REG["e_i16"][1], 32))) is None
            assert exception_code(raw.request(1, fc16(REG["sp_i16"][1], [-32, 32]))) is None
        finally:
            raw.close()
        assert abs(r.read("e") - 32 * 1e12 / 32768) <= 1e2
        assert abs(r.read("sp") + 32 * 1e12 / 32768) <= 1e2
        assert abs(r.read("pv") - 32 * 1e12 / 32768) <= 1e2
