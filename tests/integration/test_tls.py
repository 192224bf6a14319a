# SPDX-License-Identifier: MIT
"""Modbus/TCP Security (MB-TCP-Security v36): TLS 1.2+ with mutual
authentication, the client's role in its certificate (extension OID
1.3.6.1.4.1.50316.802.1, a UTF8String), and the role's access enforced per
function code and register, by the same request path as plain TCP. The CA
and every certificate are made by tlspki.py (the pki fixture: conftest.py);
the client is pymodbus's TLS client, or Python's ssl module where a handshake
is meant to fail."""

import os
import re
import socket
import ssl
import struct
import subprocess
import time

import pytest
from pymodbus.client import ModbusTcpClient, ModbusTlsClient

from pfd import REG, SLOW, Regs
from tlspki import client_ctx, start


def tls_client(d, pki, who):
    c = ModbusTlsClient("127.0.0.1", port=d.tls_port, sslctx=client_ctx(pki, who),
                        timeout=5 * SLOW, retries=0)
    assert c.connect(), f"{who}: cannot connect"
    return c


def f32(x):
    return ModbusTcpClient.convert_to_registers(float(x), ModbusTcpClient.DATATYPE.FLOAT32)


def exc(resp):
    return resp.exception_code if resp.isError() else None


def test_roles_per_function_and_register(daemon, pki):
    d = start(daemon, pki)
    viewer, operator, engineer = (tls_client(d, pki, w) for w in ("viewer", "operator",
                                                                   "engineer"))
    # read: every register, no write
    for c in (viewer, operator, engineer):
        assert exc(c.read_input_registers(0, count=20, device_id=1)) is None
        assert exc(c.read_holding_registers(0, count=66, device_id=1)) is None
    assert exc(viewer.write_registers(REG["e"][1], f32(0.5), device_id=1)) == 1
    assert exc(viewer.write_register(REG["mode"][1], 1, device_id=1)) == 1
    # operate: process inputs, mode, manual output; not the rest
    assert exc(operator.write_registers(REG["e"][1], f32(0.5), device_id=1)) is None
    assert exc(operator.write_register(REG["mode"][1], 1, device_id=1)) is None
    assert exc(operator.write_registers(REG["manual_out"][1], f32(0.001), device_id=1)) is None
    for name, value in [("failsafe_out", f32(-1e9)), ("watchdog_ms", [1]),
                        ("param_lock", [1]), ("q", f32(0.5)), ("substeps", [5]),
                        ("commit", [1]), ("command", [2])]:
        assert exc(operator.write_registers(REG[name][1], value, device_id=1)) == 1, name
    # engineer: everything, and a staged commit over TLS
    assert exc(engineer.write_registers(REG["q"][1], f32(0.8), device_id=1)) is None
    assert exc(engineer.write_register(REG["substeps"][1], 5, device_id=1)) is None
    assert exc(engineer.write_register(REG["commit"][1], 1, device_id=1)) is None
    assert Regs(engineer).read("committed_q") == pytest.approx(0.8, rel=1e-7)
    assert Regs(engineer).read("committed_substeps") == 5
    assert Regs(viewer).read("mode") == 1
    log = d.log()
    assert re.search(r"msg=write peer=127\.0\.0\.1:\d+ role=operator unit=1 reg=mode old=0 "
                     r"new=1 result=ok", log), log
    assert re.search(r"msg=write peer=127\.0\.0\.1:\d+ role=engineer unit=1 reg=q old=0\.9\d* "
                     r"new=0\.8\d* result=committed", log), log
    assert re.search(r"msg=write peer=127\.0\.0\.1:\d+ role=engineer unit=1 reg=substeps old=0 "
                     r"new=5 result=committed", log), log
    assert re.search(r"msg=write-refused peer=\S+ role=viewer unit=1 .*reason=access", log)


def test_role_without_access_reads_nothing(daemon, pki):
    d = start(daemon, pki)
    c = tls_client(d, pki, "auditor")
    assert exc(c.read_input_registers(0, count=2, device_id=1)) == 1


def handshake_refused(d, pki, who, max_version=None):
    """Whether the daemon refuses this client at the handshake: no Modbus
    answer ever comes. TLS 1.3 clients finish their side first and learn
    it from the server's alert at the first read."""
    raw = socket.create_connection(("127.0.0.1", d.tls_port), timeout=5 * SLOW)
    try:
        s = client_ctx(pki, who, max_version).wrap_socket(raw)
        s.sendall(struct.pack(">HHHBBHH", 1, 0, 6, 1, 4, 0, 1))
        return s.recv(64) == b""
    except (ssl.SSLError, ConnectionResetError, BrokenPipeError):
        return True
    finally:
        raw.close()


@pytest.mark.parametrize("who,reason", [
    ("expired", "certificate has expired"),
    ("otherca", "unable to get local issuer certificate"),
    (None, "peer did not return a certificate"),
    ("norole", "no role extension in the client certificate"),
    ("intruder", "the certificate's role is not in tls_roles"),
    ("badder", "malformed role extension in the client certificate"),
])
def test_bad_certificates_are_refused_at_the_handshake(daemon, pki, who, reason):
    d = start(daemon, pki)
    assert handshake_refused(d, pki, who)
    assert handshake_refused(d, pki, who, ssl.TLSVersion.TLSv1_2)
    deadline = time.monotonic() + 10 * SLOW
    while reason not in d.log():
        assert time.monotonic() < deadline, d.log()
        time.sleep(0.05)
    assert "msg=tls-refused" in d.log()
    # A good client is still served.
    assert exc(tls_client(d, pki, "viewer").read_input_registers(0, count=2, device_id=1)) is None


def test_plain_tcp_next_to_tls(daemon, pki):
    """Plain TCP stays on (loopback by default); plain_access sets what it
    may do, and none closes the plain listener."""
    d = start(daemon, pki, "--plain-access", "read")
    plain = d.client()
    assert exc(plain.read_input_registers(0, count=2, device_id=1)) is None
    assert exc(plain.write_registers(REG["e"][1], f32(0.5), device_id=1)) == 1
    assert exc(tls_client(d, pki, "operator").write_registers(REG["e"][1], f32(0.5),
                                                              device_id=1)) is None
    d2 = start(daemon, pki, "--plain-access", "none")
    assert "msg=listening addr=none" in d2.log()


# A request as raw MBAP bytes: FC04, two input registers from 0, unit 1;
# its answer is 13 bytes (MBAP 7, function, byte count, 4 data).
READ_IR = struct.pack(">HHHBBHH", 1, 0, 6, 1, 4, 0, 2)
READ_IR_ANSWER = 13


def tls_socket(d, pki):
    raw = socket.create_connection(("127.0.0.1", d.tls_port), timeout=5 * SLOW)
    return client_ctx(pki, "viewer").wrap_socket(raw)


def recv_exactly(s, n):
    got = b""
    while len(got) < n:
        part = s.recv(n - len(got))
        assert part, f"closed after {len(got)} of {n} bytes"
        got += part
    return got


def test_requests_across_records(daemon, pki):
    """The daemon takes TLS records whole and keeps the decrypted bytes
    of the next request: two requests in one record are both answered, and
    one split over three records is answered once it is whole."""
    d = start(daemon, pki)
    s = tls_socket(d, pki)
    s.sendall(READ_IR + READ_IR)
    answers = recv_exactly(s, 2 * READ_IR_ANSWER)
    assert answers[:2] == READ_IR[:2] and answers[READ_IR_ANSWER:][:2] == READ_IR[:2]
    for part in (READ_IR[:3], READ_IR[3:9], READ_IR[9:]):
        s.sendall(part)
        time.sleep(0.05)
    assert recv_exactly(s, READ_IR_ANSWER)[:2] == READ_IR[:2]
    s.close()


@pytest.mark.parametrize("what,reason", [("bad-frame", "bad-frame"),
                                         ("junk-record", "bad-record"),
                                         ("huge-record", "bad-record")])
def test_junk_after_the_handshake_ends_the_connection(daemon, pki, what, reason):
    """A whole application-data record waiting keeps a TLS connection from
    eviction (docs/pneufracd.md, "The shield on TLS connections"), so one
    that does not decrypt, one longer than TLS allows, and one that holds
    a bad MBAP header (protocol id 7) must each end the connection, as a
    bad plain frame does."""
    d = start(daemon, pki, "--verbose")
    s = tls_socket(d, pki)
    port = s.getsockname()[1]
    if what == "bad-frame":
        s.sendall(READ_IR[:2] + b"\x00\x07" + READ_IR[4:])
    else:  # on the wire, under the TLS layer
        raw = socket.socket(fileno=os.dup(s.fileno()))
        n = 40 if what == "junk-record" else 16384 + 2048 + 1
        raw.sendall(bytes([0x17, 3, 3, n >> 8, n & 0xFF]) + (os.urandom(n) if n == 40 else b""))
        raw.close()
    pat = rf"msg=client-closed peer=127\.0\.0\.1:{port} reason=(\S+)"
    deadline = time.monotonic() + 10 * SLOW
    while not re.search(pat, d.log()):
        assert time.monotonic() < deadline, d.log()[-2000:]
        time.sleep(0.02)
    assert re.search(pat, d.log()).group(1) == reason
    s.close()


def key_updates(d, pki, pause, seconds):
    """Key updates from an authenticated TLS 1.3 client (openssl s_client
    sends one for each input line "k"), one every @p pause s for at most
    @p seconds, until daemon @p d closes the connection: @return the
    reason it logged, None if it did not close it."""
    p = subprocess.Popen(["openssl", "s_client", "-connect", f"127.0.0.1:{d.tls_port}",
                          "-CAfile", pki["ca"], "-cert", pki["viewer"][0],
                          "-key", pki["viewer"][1], "-tls1_3", "-no_ign_eof"],
                         stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    closed = re.compile(r"msg=client-closed peer=127\.0\.0\.1:\d+ reason=(\S+)")
    try:
        deadline = time.monotonic() + 10 * SLOW
        while "msg=client-connected" not in d.log():
            assert time.monotonic() < deadline, d.log()[-2000:]
            time.sleep(0.02)
        end = time.monotonic() + seconds
        while not closed.search(d.log()) and time.monotonic() < end:
            try:
                p.stdin.write(b"k\n")
                p.stdin.flush()
            except BrokenPipeError:
                break
            time.sleep(pause)
        # closed while the key updates still came, not once they stopped
        m = closed.search(d.log())
    finally:
        p.kill()
        p.wait()
    return m.group(1) if m else None


def test_records_without_a_request_end_at_the_deadline(daemon, pki):
    """TLS 1.3 key updates are records that bring no byte of a request
    (as empty records are): each keeps a whole record waiting, and so the
    slot, until the client's thread takes it. A client that sends them
    without end must still be closed at its first-request deadline. They
    come 16 to the deadline, below the count that ends a connection at
    once (test_records_without_a_request_are_bounded)."""
    first_ms = int(1000 * SLOW)
    d = start(daemon, pki, "--verbose", "--first-request-timeout-ms", str(first_ms))
    assert key_updates(d, pki, first_ms / 16000, 5 * first_ms / 1000) == \
        "first-request-timeout", d.log()[-2000:]


def test_records_without_a_request_are_bounded(daemon, pki):
    """Key updates from an authenticated client whose deadline is far off
    (an idle timeout may even be none): each whole record waiting keeps
    the slot pending, so more than 32 of them between two requests end
    the connection at once, with its own reason (before: only the
    deadline, here a minute away, ended it). 10 s at most, far past 33
    key updates."""
    d = start(daemon, pki, "--verbose", "--first-request-timeout-ms", "60000")
    assert key_updates(d, pki, 0.05, 10.0) == "empty-records", d.log()[-2000:]


def test_tls_needs_its_files(tmp_path):
    import subprocess
    from pfd import DAEMON
    p = subprocess.run([DAEMON, "--listen", "127.0.0.1:0", "--tls-listen", "127.0.0.1:0",
                        "--run-for", "1"], capture_output=True, text=True, timeout=30)
    # a bad combination of arguments: exit 2 before the loop starts (was 1,
    # found by the server after the loop had started)
    assert p.returncode == 2 and "--tls-listen needs --tls-cert, --tls-key and --tls-ca" in p.stderr
    assert p.stderr.count("\n") == 1, p.stderr
    p = subprocess.run([DAEMON, "--tls-roles", "viewer:god"], capture_output=True, text=True,
                       timeout=30)
    assert p.returncode == 2 and "--tls-roles" in p.stderr, p.stderr


@pytest.mark.parametrize("what", ["directory", "not-pem"])
def test_unusable_tls_files_are_a_usage_error(tmp_path, what):
    """TLS files that exist but cannot be used (a directory: fopen() reads
    it on Linux; a file that is not PEM) are refused with exit 2 before
    the loop starts (before: the loop started, then the server failed with
    exit 1)."""
    from pfd import DAEMON
    f = tmp_path
    if what == "not-pem":
        f = tmp_path / "x.pem"
        f.write_text("not a certificate\n")
    p = subprocess.run([DAEMON, "--listen", "127.0.0.1:0", "--tls-listen", "127.0.0.1:0",
                        "--tls-cert", str(f), "--tls-key", str(f), "--tls-ca", str(f),
                        "--run-for", "1"], capture_output=True, text=True, timeout=30)
    assert p.returncode == 2 and f"--tls-cert {f}" in p.stderr, p.stderr
    assert "loop-start" not in p.stderr and "listening" not in p.stderr, p.stderr
