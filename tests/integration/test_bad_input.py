# SPDX-License-Identifier: MIT
"""Bad input: exception 02 for unknown or read-only addresses, 03 for
invalid values and counts, 01 for unsupported functions and refused
states; after any of them nothing has changed. A refused commit leaves the
old parameters running."""

import struct

import pytest

from pfd import (HOLD_SIZE, INPUT_SIZE, REG, Raw, Regs, exception_code, fc03, fc04, fc06, fc16,
                 fc23, simulate_exchanges, wait_until)


def hold_image(c, unit=1):
    regs = []
    for start in range(0, HOLD_SIZE, 100):
        rr = c.read_holding_registers(start, count=min(100, HOLD_SIZE - start), device_id=unit)
        assert not rr.isError()
        regs += rr.registers
    return regs


def committed_image(c, unit=1):
    rr = c.read_input_registers(34, count=INPUT_SIZE - 34, device_id=unit)
    assert not rr.isError()
    return rr.registers


def state(c):
    return hold_image(c), committed_image(c)


def f32(x):
    hi, lo = struct.unpack(">HH", struct.pack(">f", x))
    return [hi, lo]


def raw_f32(raw, name):
    """A float holding register as the Raw connection sees it."""
    rsp = raw.request(1, fc03(REG[name][1], 2))
    return struct.unpack(">f", rsp[2:6])[0]


@pytest.fixture
def lockstep(daemon):
    d = daemon("--clock", "external")
    return d, d.client(), Raw(d.port)


BAD = [
    # (what, unit, pdu, exception)
    ("read past the holding map", 1, fc03(HOLD_SIZE, 1), 2),
    ("read across the end of the holding map", 1, fc03(HOLD_SIZE - 6, 10), 2),
    ("read past the input map", 1, fc04(INPUT_SIZE, 1), 2),
    ("read far away", 1, fc03(40000, 4), 2),
    ("write an unknown address", 1, fc06(HOLD_SIZE, 1), 2),
    ("write a read-only holding register", 1, fc06(REG["hold_status"][1], 1), 2),
    ("write the low half of a float", 1, fc06(REG["e"][1] + 1, 0x3F80), 2),
    ("FC16 ending in half a float", 1, fc16(REG["e"][1], [0x3F80]), 2),
    ("FC16 starting in half a float", 1, fc16(REG["e"][1] + 1, [0, 0, 0]), 2),
    ("FC16 over the end", 1, fc16(64, [0, 0, 0]), 2),
    ("read count 0", 1, fc03(0, 0), 3),
    ("read count 126", 1, fc03(0, 126), 3),
    ("huge read count", 1, fc04(0, 65535), 3),
    ("FC16 count 124", 1, fc16(0, [0], count=124), 3),
    ("FC16 count 65535", 1, fc16(0, [0, 0], count=65535), 3),
    ("FC16 count 0", 1, fc16(0, [], count=0), 3),
    ("FC16 byte count mismatch", 1, fc16(REG["mode"][1], [1], nbytes=4) + b"\0\0", 3),
    ("mode 2", 1, fc06(REG["mode"][1], 2), 3),
    ("input_sel 7", 1, fc06(REG["input_sel"][1], 7), 3),
    ("watchdog 60001 ms", 1, fc06(REG["watchdog_ms"][1], 60001), 3),
    ("param_lock 2", 1, fc06(REG["param_lock"][1], 2), 3),
    ("commit 2", 1, fc06(REG["commit"][1], 2), 3),
    ("command 9", 1, fc06(REG["command"][1], 9), 3),
    ("tick 0", 1, fc06(REG["tick"][1], 0), 3),
    ("config 4", 1, fc06(REG["config"][1], 4), 3),
    ("arith 2", 1, fc06(REG["arith"][1], 2), 3),
    ("e NaN", 1, fc16(REG["e"][1], f32(float("nan"))), 3),
    ("e infinite", 1, fc16(REG["e"][1], f32(float("inf"))), 3),
    ("e 1e10", 1, fc16(REG["e"][1], f32(1e10)), 3),
    ("beta 1.5", 1, fc16(REG["beta"][1], f32(1.5)), 3),
    ("beta 0", 1, fc16(REG["beta"][1], f32(0.0)), 3),
    ("q -0.1", 1, fc16(REG["q"][1], f32(-0.1)), 3),
    ("fs 0", 1, fc16(REG["fs"][1], f32(0.0)), 3),
    ("fs 1e6", 1, fc16(REG["fs"][1], f32(1e6)), 3),
    ("substeps 10001", 1, fc06(REG["substeps"][1], 10001), 3),
    ("tau negative", 1, fc16(REG["tau"][1], f32(-1.0)), 3),
    ("valid e with an invalid mode, one FC16", 1,
     fc16(REG["e"][1], f32(0.5) + [0, 0, 0, 0, 0, 0, 0, 5]), 3),
    ("unsupported function 01", 1, struct.pack(">BHH", 1, 0, 8), 1),
    ("unsupported function 05", 1, struct.pack(">BHH", 5, 0, 0xFF00), 1),
    ("unsupported function 43", 1, bytes([0x2B, 0x0E, 0x01, 0x00]), 1),
    ("unknown unit id", 9, fc03(0, 1), 0x0B),
]


@pytest.mark.parametrize("what,unit,pdu,code", BAD, ids=[b[0] for b in BAD])
def test_exception_and_nothing_changed(lockstep, what, unit, pdu, code):
    _, c, raw = lockstep
    before = state(c)
    rsp = raw.request(unit, pdu)
    assert exception_code(rsp) == code, f"{what}: response {rsp.hex()}"
    assert rsp[0] == pdu[0] | 0x80
    assert state(c) == before, what
    # The connection is still usable.
    assert exception_code(raw.request(1, fc03(0, 2))) is None


def test_tick_needs_external_clock(daemon):
    d = daemon()
    raw = Raw(d.port)
    assert exception_code(raw.request(1, fc06(REG["tick"][1], 1))) == 1


def test_read_only_mode(daemon):
    d = daemon("--read-only")
    c = d.client()
    raw = Raw(d.port)
    before = state(c)
    for pdu in (fc06(REG["mode"][1], 1), fc16(REG["e"][1], f32(1.0)),
                fc06(REG["commit"][1], 1), fc06(999, 1)):
        assert exception_code(raw.request(1, pdu)) == 1
    assert state(c) == before
    assert Regs(c).read("status") & (1 << 5)


def test_param_lock_register(lockstep):
    _, c, raw = lockstep
    r = Regs(c)
    r.write("param_lock", 1)
    before = state(c)
    assert exception_code(raw.request(1, fc16(REG["q"][1], f32(0.5)))) == 1
    assert exception_code(raw.request(1, fc06(REG["commit"][1], 1))) == 1
    # Discarding the staged set writes staged registers: refused alike.
    assert exception_code(raw.request(1, fc06(REG["command"][1], 1))) == 1
    assert state(c) == before
    r.write("e", 0.25)  # live registers stay writable
    r.write("param_lock", 0)
    r.write("q", 0.5)
    r.write("commit", 1)
    assert abs(r.read("committed_q") - 0.5) < 1e-7


def test_param_lock_keeps_staged_changes(lockstep):
    """Staged, then locked: command 1 must not discard the staged set."""
    _, c, raw = lockstep
    r = Regs(c)
    r.write("q", 0.5)
    r.write("param_lock", 1)
    assert exception_code(raw.request(1, fc06(REG["command"][1], 1))) == 1
    assert abs(r.read("q") - 0.5) < 1e-7
    assert r.read("status") & (1 << 7)  # staged still differs


def test_fc23_reads_what_fc03_reads(lockstep):
    """FC23 reads after its write, and what it reads is the register
    image: action registers read 0 even in the range just written, and an
    int16 mirror reads its rendered value."""
    _, c, raw = lockstep
    samples = Regs(c).read("samples")
    rsp = raw.request(1, fc23(REG["command"][1], 2, REG["tick"][1], [7]))
    assert exception_code(rsp) is None, rsp.hex()
    assert struct.unpack(">BB2H", rsp) == (23, 4, 0, 0)
    assert Regs(c).read("samples") == samples + 7
    rsp = raw.request(1, fc03(REG["command"][1], 2))
    assert struct.unpack(">BB2H", rsp) == (3, 4, 0, 0)
    # The write (e_i16) inside the read range (e .. pv_i16): the answer
    # must equal a following FC03, not echo the raw value.
    rsp = raw.request(1, fc23(REG["e"][1], 8, REG["e_i16"][1], [12345]))
    assert exception_code(rsp) is None
    assert rsp[2:] == raw.request(1, fc03(REG["e"][1], 8))[2:]
    # Write and read exactly the same register.
    rsp = raw.request(1, fc23(REG["tick"][1], 1, REG["tick"][1], [3]))
    assert struct.unpack(">BBH", rsp) == (23, 2, 0)


def test_param_lock_flag_cannot_be_undone(daemon):
    d = daemon("--param-lock")
    r = Regs(d.client())
    raw = Raw(d.port)
    assert r.read("param_lock") == 1
    assert exception_code(raw.request(1, fc06(REG["param_lock"][1], 0))) == 1
    assert exception_code(raw.request(1, fc16(REG["q"][1], f32(0.5)))) == 1
    assert r.read("param_lock") == 1


def test_refused_commit_keeps_old_parameters_running(lockstep):
    """pmin > pmax passes each register's range but not the set: the commit
    is refused with exception 03, the status names pmax, and the loop keeps
    running Example 6 as if nothing had happened."""
    _, c, raw = lockstep
    r = Regs(c)
    ref = simulate_exchanges(1000, r.read("substeps_used"), "--config", "dd", "--duration", "0.2")
    r.write("e", 1.0)
    pcs = []
    for _ in range(100):
        r.tick(1)
        pcs.append(r.read("pc"))
    committed = committed_image(c)

    # Staged and committed in one FC16 (pmin, pmax are adjacent): refused.
    pmin = REG["pmin"][1]
    rsp = raw.request(1, fc16(pmin, f32(50.0) + f32(2.0)))
    assert exception_code(rsp) is None  # staging alone is fine
    rsp = raw.request(1, fc06(REG["commit"][1], 1))
    assert exception_code(rsp) == 3
    assert r.read("commit_result") == 1
    assert r.read("commit_err_addr") == REG["pmax"][1]
    assert r.read("commit_err_param") == 8  # PF_P_PMAX in pf_status.h
    assert r.read("status") & (1 << 2)
    assert committed_image(c) == committed
    # Staging + commit in one request: refused, and the staged write of
    # that request is not applied either. Staged registers are the
    # connection's own: raw sees its staging, c does not.
    q = REG["q"][1]
    before_q = raw_f32(raw, "q")
    rsp = raw.request(1, fc16(q, f32(0.7)))
    assert exception_code(rsp) is None
    rsp = raw.request(1, fc16(REG["commit"][1], [1]))
    assert exception_code(rsp) == 3
    assert committed_image(c) == committed
    assert raw_f32(raw, "q") != before_q  # staged by the earlier, valid request
    assert r.read("q") == before_q

    for _ in range(100):
        r.tick(1)
        pcs.append(r.read("pc"))
    worst = max(abs(a - float(row["pc"])) for a, row in zip(pcs, ref))
    assert len(pcs) == 200 and worst <= 1e-6

    # Discard the staged changes: staged equals committed again.
    assert struct.unpack(">BBH", raw.request(1, fc04(REG["status"][1], 1)))[2] & (1 << 7)
    assert exception_code(raw.request(1, fc06(REG["command"][1], 1))) is None
    assert not struct.unpack(">BBH", raw.request(1, fc04(REG["status"][1], 1)))[2] & (1 << 7)
    assert raw_f32(raw, "pmin") == r.read("committed_pmin")


def test_staged_write_and_refused_commit_in_one_request(lockstep):
    """One FC16 over commit, command, tick and the staged block up to pmax:
    the staged pmin > pmax makes the commit fail, so the whole request is
    refused: no staged value, no command, no tick."""
    _, c, raw = lockstep
    before = state(c)
    samples = Regs(c).read("samples")
    hold = hold_image(c)
    pmin = REG["pmin"][1]
    payload = [1, 1, 1]  # commit 1, command 1 (discard staged), tick 1
    payload += hold[REG["config"][1]:pmin]
    payload += f32(50.0) + f32(2.0)
    rsp = raw.request(1, fc16(REG["commit"][1], payload))
    assert exception_code(rsp) == 3
    after = state(c)
    assert after[1] == before[1]
    assert after[0][pmin:pmin + 4] == before[0][pmin:pmin + 4]
    assert Regs(c).read("samples") == samples


def _closed_at_once(port):
    import socket
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    try:
        s.sendall(bytes.fromhex("000100000006010300000001"))
        return s.recv(64) == b""
    except ConnectionResetError:
        return True
    finally:
        s.close()


def test_max_clients(daemon):
    d = daemon("--max-clients", "2")
    a, b = Raw(d.port), Raw(d.port)
    assert exception_code(a.request(1, fc03(0, 2))) is None
    assert exception_code(b.request(1, fc03(0, 2))) is None
    assert _closed_at_once(d.port)
    assert "reason=max-clients" in d.log()
    b.close()
    # The slot frees once the thread is reaped (within ~200 ms).
    wait_until(lambda: not _closed_at_once(d.port), 10, "client slot freed", step=0.1)
    assert exception_code(a.request(1, fc03(0, 2))) is None


def test_allow_list(daemon):
    d = daemon("--allow", "10.0.0.0/8, 192.168.1.7")
    assert _closed_at_once(d.port)
    assert "reason=not-in-allow-list" in d.log()
    d2 = daemon("--allow", "127.0.0.1/32")
    assert exception_code(Raw(d2.port).request(1, fc03(0, 2))) is None


def test_bad_command_lines(tmp_path):
    import subprocess
    from pfd import DAEMON
    for args, text in [(["--listen", "localhost"], "--listen"),
                       (["--listen", "127.0.0.1:70000"], "--listen"),
                       (["--allow", "10.0.0.0/33"], "prefix"),
                       (["--max-clients", "0"], "--max-clients"),
                       (["--fs", "1e9"], "--fs"),
                       (["--clock", "gps"], "--clock"),
                       (["--bogus"], "unknown option"),
                       (["--config", str(tmp_path / "none.conf")],
                        "cannot open: No such file or directory (pneufracd --init-config"),
                       (["--config", str(tmp_path)], "read error"),
                       (["--config", "x.conf", "--fs", "100"], "--config")]:
        p = subprocess.run([DAEMON, *args, "--run-for", "1"], capture_output=True, text=True,
                           timeout=30)
        assert p.returncode == 2, (args, p.stderr)
        assert p.stderr.startswith("pneufracd: ") and text in p.stderr, (args, p.stderr)
        assert p.stderr.count("\n") == 1, p.stderr


def test_settings_that_go_together_are_refused_before_start(tmp_path):
    """A combination of settings the server cannot serve is bad arguments
    (exit 2, one line, nothing started), from the command line or the
    config file: before, the loop started and the server then exited 1,
    and a missing certificate file read only "--tls-cert FILE: failed"."""
    import subprocess
    from pfd import DAEMON
    conf = tmp_path / "tls.conf"
    conf.write_text("[daemon]\ntls_listen = 127.0.0.1:0\n\n[instance 1]\nconfig = p\n")
    sealed = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True,
                            text=True, timeout=30)
    assert sealed.returncode == 0, sealed.stderr
    missing = str(tmp_path / "none.pem")
    for args, text in [(["--plain-access", "none"], "--plain-access none needs --tls-listen"),
                       (["--config", str(conf)], "--tls-listen needs --tls-cert"),
                       (["--tls-listen", "127.0.0.1:0", "--tls-cert", missing, "--tls-key",
                         missing, "--tls-ca", missing],
                        f"--tls-cert {missing} (config key tls_cert): cannot read: No such "
                        "file")]:
        p = subprocess.run([DAEMON, "--listen", "127.0.0.1:0", "--rt-priority", "0",
                            "--no-mlock", *args, "--run-for", "1"], capture_output=True,
                           text=True, timeout=30)
        assert p.returncode == 2, (args, p.stderr)
        assert p.stderr.startswith("pneufracd: ") and text in p.stderr, (args, p.stderr)
        assert p.stderr.count("\n") == 1, p.stderr       # no loop-start lines before it
