# SPDX-License-Identifier: MIT
"""pneufracd under a hostile network (issue 12): function codes 0x80 and
up, the file-size limit, running out of file descriptors, client slots
under 1000 hostile sockets, the parameter lock, per-client staging, the
plausibility check and the audit log. Every server binds to 127.x; every
attack loop is bounded in count and time."""

import os
import random
import re
import resource
import shutil
import signal
import socket
import ssl
import struct
import subprocess
import threading
import time

import pytest

from pfd import (DAEMON, HANG_S, REG, SLOW, Daemon, Raw, Regs, exception_code, f32, fc03, simulate,
                 wait_until)
from tlspki import client_ctx, start as start_tls


def adu(tid, unit, pdu):
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


@pytest.fixture
def conf(tmp_path):
    path = tmp_path / "pneufracd.conf"
    path.write_text(subprocess.run([DAEMON, "--print-default-config"], check=True,
                                   capture_output=True, text=True).stdout)
    return path


# ---- F4: function codes 0x80 and up --------------------------------------

@pytest.mark.parametrize("fc", [0x80, 0x81, 0x83, 0x86, 0x90, 0xAB, 0xFF])
def test_function_codes_0x80_and_up(daemon, fc):
    """The exception's function code is the request's with bit 7 set:
    FC 0x83 gets 83 01, not 03 01 (what libmodbus 3.1.6 sent). Raw
    sockets, with and without data after the function code."""
    d = daemon()
    raw = Raw(d.port)
    for payload in (b"", b"\x00\x00\x00\x01", bytes(range(200))):
        assert raw.request(1, bytes([fc]) + payload) == bytes([fc, 0x01])
    assert exception_code(raw.request(1, fc03(0, 2))) is None  # still in step


# ---- F2: the file-size limit ---------------------------------------------

def test_file_size_limit(tmp_path, conf):
    """Under `ulimit -f` (RLIMIT_FSIZE) smaller than the config file, a
    commit's write fails with EFBIG: the daemon answers exception 04 with
    commit_result 5 and keeps running, instead of dying of SIGXFSZ."""
    before = conf.read_bytes()
    d = Daemon(tmp_path, "--config", str(conf), limits={resource.RLIMIT_FSIZE: 256})
    try:
        r = Regs(d.client())
        r.write("q", 0.5)
        resp = r.write_raw("commit", 1)
        assert resp.isError() and resp.exception_code == 4, resp
        assert r.read("commit_result") == 5 and r.read("committed_q") == f32(0.5)
        n = r.read("samples")
        time.sleep(0.05)
        assert r.read("samples") > n and d.proc.poll() is None
        assert "msg=persist-failed" in d.log() and "File too large" in d.log()
    finally:
        rc = d.stop()
    assert rc == 1, d.log()[-2000:]  # the shutdown's write failed too: status 1, not 153
    assert conf.read_bytes() == before


# ---- F3: out of file descriptors -----------------------------------------

def cpu_seconds(pid):
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / __import__("os").sysconf("SC_CLK_TCK")


def test_fd_exhaustion(tmp_path):
    """With 40 fds (soft and hard) and room for 64 clients, the daemon runs
    out of fds. It says so (rate-limited), closes each further connection
    at once instead of leaving it to time out, does not spin, and serves
    again as soon as fds are free."""
    d = Daemon(tmp_path, "--clock", "external", "--max-clients", "64",
               "--max-clients-per-addr", "64", "--first-request-timeout-ms", "60000",
               limits={resource.RLIMIT_NOFILE: (40, 40)})
    held = []
    try:
        assert "msg=fd-limit" in d.log()
        for _ in range(60):
            s = socket.create_connection(("127.0.0.1", d.port), timeout=5 * SLOW)
            held.append(s)
        deadline = time.monotonic() + 10 * SLOW
        while "msg=accept-failed" not in d.log():
            assert time.monotonic() < deadline, d.log()
            time.sleep(0.05)
        # A newcomer learns at once that it is refused.
        for _ in range(5):
            s = socket.create_connection(("127.0.0.1", d.port), timeout=5 * SLOW)
            s.settimeout(3 * SLOW)
            s.sendall(adu(1, 1, fc03(0, 1)))
            try:
                assert s.recv(16) == b""
            except ConnectionResetError:
                pass
            s.close()
        # No spinning: the process is idle while its fds stay exhausted.
        t0 = cpu_seconds(d.proc.pid)
        time.sleep(2.0)
        cpu = cpu_seconds(d.proc.pid) - t0
        print({"held": len(held), "cpu_s_in_2s": cpu,
               "accept_failed_lines": d.log().count("msg=accept-failed")})
        assert cpu < 0.3, "the accept loop spins"
        assert d.log().count("msg=accept-failed") <= 10  # rate-limited
        for s in held:
            s.close()
        held = []
        deadline = time.monotonic() + 10 * SLOW
        while True:
            try:
                assert Regs(d.client()).read("unit_id") == 1
                break
            except Exception:
                assert time.monotonic() < deadline, d.log()[-2000:]
                time.sleep(0.2)
    finally:
        for s in held:
            s.close()
        assert d.stop() == 0, d.log()[-2000:]


# ---- O1: client slots ------------------------------------------------------

def connect_from(addr, port):
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind((addr, 0))
    s.settimeout(5 * SLOW)
    s.connect(("127.0.0.1", port))
    return s


def ask(s, tid=1):
    """One FC03 on socket @p s; True if answered."""
    s.sendall(adu(tid, 1, fc03(0, 2)))
    try:
        return len(s.recv(64)) > 0
    except OSError:
        return False


def test_slot_policy(daemon):
    """Per-address limit, and who is evicted for whom: an address at its
    limit makes room among its own connections; a full table gives up the
    connections that never completed a request, never a client that polls."""
    d = daemon("--max-clients", "4", "--max-clients-per-addr", "2",
               "--first-request-timeout-ms", "500")
    a = connect_from("127.0.0.1", d.port)
    assert ask(a)
    time.sleep(0.6)  # a: idle past the protection time (500 ms)
    b = connect_from("127.0.0.1", d.port)
    assert ask(b)
    c = connect_from("127.0.0.1", d.port)  # third from 127.0.0.1: a (idle longest) goes
    assert ask(c)
    assert not ask(a) and ask(b)
    f = connect_from("127.0.0.1", d.port)  # b and c poll: f is refused, they stay
    assert not ask(f) and ask(b) and ask(c)
    idle = [connect_from(f"127.0.0.{k}", d.port) for k in (2, 3)]  # never ask
    time.sleep(0.1)
    e = connect_from("127.0.0.4", d.port)  # table full: an idle one goes
    assert ask(e)
    assert ask(b) and ask(c)
    log = d.log()
    assert re.search(r"msg=client-evicted peer=127\.0\.0\.1:\d+ active=1 .*"
                     r"reason=max-clients-per-addr", log), log
    assert re.search(r"msg=client-evicted peer=127\.0\.0\.[23]:\d+ active=0 .*"
                     r"reason=max-clients", log), log
    for s in [a, b, c, e, f] + idle:
        s.close()


def pin_to_one_cpu(pid):
    """Every thread of process @p pid, and so every thread it starts later,
    onto one CPU (as `taskset -a -p`): which of its threads runs first is
    then the scheduler's choice on one CPU, not a race between two."""
    cpu = min(os.sched_getaffinity(pid))
    for tid in os.listdir(f"/proc/{pid}/task"):
        os.sched_setaffinity(int(tid), {cpu})


def closed_reason(d, port, seconds):
    """The reason daemon @p d logged for closing 127.0.0.1:@p port, or None
    if it logs none within @p seconds (times SLOW): a connection refused at
    accept has no thread, and so no such line."""
    pat = re.compile(rf"msg=client-closed peer=127\.0\.0\.1:{port} reason=(\S+)")
    deadline = time.monotonic() + seconds * SLOW
    while True:
        m = pat.search(d.log())
        if m or time.monotonic() >= deadline:
            return m.group(1) if m else None
        time.sleep(0.01)


# The first bytes of a TLS ClientHello: a handshake record's header that
# announces 200 bytes, which never come (a half-open TLS socket).
HALF_HELLO = bytes([0x16, 0x03, 0x01, 0x00, 0xC8])


def waiting_request_round(d, r, split, tls=None):
    """One round of test_waiting_request_keeps_its_slot; @p tls: the
    client's SSLContext, for the TLS listener. @return whether the client
    was answered, and its port."""
    req = adu(r + 1, 1, fc03(0, 2))
    legit = connect_from("127.0.0.1", d.tls_port if tls else d.port)
    if tls:
        # The handshake, with the daemon running; TLS 1.3's client is done
        # before the server has checked its Finished, so wait for the
        # client's thread to be past the handshake. A client refused at
        # accept (the last round's slot not yet reaped: the daemon closes
        # it with no client-closed line) sees the handshake end at EOF; the
        # caller tries that round again, as it does a plain one refused
        # (an ASan run at load 6 met it, 2026-11-28).
        port = legit.getsockname()[1]
        try:
            legit = tls.wrap_socket(legit)
        except (ssl.SSLError, OSError):
            legit.close()
            return False, port
        me = rf"msg=client-connected peer=127\.0\.0\.1:{legit.getsockname()[1]} "
        wait_until(lambda: re.search(me, d.log()), 10, "the TLS handshake")
    if split:  # the header now, and time for the client's thread to take it
        legit.sendall(req[:7])
        time.sleep(0.2)
    os.kill(d.proc.pid, signal.SIGSTOP)
    hostile = []
    try:
        try:
            legit.sendall(req[7:] if split else req)
        except OSError:
            pass  # closed already: the recv below says so
        hostile = [connect_from(f"127.0.3.{k + 1}", d.tls_port if tls else d.port)
                   for k in range(4)]
        for s in hostile:
            s.sendall(HALF_HELLO if tls else adu(0, 1, fc03(0, 2))[:5])
    finally:
        os.kill(d.proc.pid, signal.SIGCONT)
    try:
        answered = len(legit.recv(64)) > 0
    except OSError:
        answered = False
    port = legit.getsockname()[1]
    # Let the daemon take every hostile socket (refused or evicted: closed;
    # the one left in a slot: 1 s), so that none is left in the backlog to
    # meet the next round's client while it has sent only a header.
    for s in hostile:
        s.settimeout(1 * SLOW)
        try:
            s.recv(1)
        except OSError:
            pass
    for s in hostile + [legit]:
        s.close()
    return answered, port


@pytest.mark.parametrize("tls,split", [(False, False), (False, True), (True, False), (True, True)],
                         ids=["whole", "split", "tls-whole", "tls-split"])
def test_waiting_request_keeps_its_slot(daemon, request, tls, split):
    """A client whose whole request waits unread, because the daemon's
    threads have not run yet, keeps its slot against sockets that sent
    half a header. Under load 12-14 test_1000_hostile_sockets lost its
    poller that way: its first request was waiting, and as the oldest
    newcomer that had sent something it went before the half-open ones.
    Here the daemon is stopped (SIGSTOP) while the client sends its
    request (whole; or, split, the rest of it after its thread has taken
    the header) and four hostile sockets connect and send half a header: a
    CPU-starved daemon, on purpose and bounded. It then runs on one CPU,
    where its accept thread usually takes the backlog before the client's
    thread reads; with one slot, the first hostile socket decides. Without
    the fix the client lost 30 of 40 rounds (whole; 5 runs, load 8.5); one
    round of 8 lost (accepted, then closed unanswered) fails the test. A
    round in which the client was refused instead (its previous
    connection's slot not yet reaped) is tried again, at most 5 times.
    With TLS the client's handshake is done before the daemon stops (each
    record of the request is one sendall), and the hostile sockets send
    the start of a ClientHello: without the TLS shield the client lost
    every round."""
    args = ("--max-clients", "1", "--first-request-timeout-ms", "60000",
            "--byte-timeout-ms", "10000", "--verbose")
    ctx = None
    if tls:
        d = start_tls(daemon, request.getfixturevalue("pki"), *args)
        ctx = client_ctx(request.getfixturevalue("pki"), "viewer")
    else:
        d = daemon(*args)
    pin_to_one_cpu(d.proc.pid)
    lost, refused = [], 0
    for r in range(8):
        for _ in range(5):
            answered, port = waiting_request_round(d, r, split, ctx)
            # an answered client's slot must be free again before the next round
            # A client closed unanswered had been accepted: it lost its slot
            # (reason=evicted; before the fix, send-failed for one evicted
            # after its thread had read). One with no such line was refused.
            reason = closed_reason(d, port, 10 if answered else 2)
            assert reason is not None or not answered, "the client's connection closed"
            if answered or reason is not None:
                lost += [] if answered else [(port, reason)]
                break
            refused += 1
        else:
            pytest.fail(f"round {r}: neither answered nor accepted in 5 tries\n{d.log()[-2000:]}")
    assert not lost, (lost, refused, d.log()[-2000:])
    assert "msg=client-refused" in d.log()


def test_1000_hostile_sockets(daemon):
    """O1: 1000 hostile sockets come and go from 127.0.1.x (idle, half-open:
    half a header then silence, slowloris: one byte of a long frame every
    80 ms), 48 at a time, against 16 slots. Meanwhile a client that polls,
    and a client that connects afresh for each request, from 127.0.0.1, are
    each served every time: no request goes unanswered for HANG_S, where
    the lock-out of O1 lasted idle_timeout_s (300 s). The response times
    are printed (the issue asks for 1 s), not asserted: they measure the
    machine's load as much as the daemon.

    The poller's first request and the flood's first wave reach the
    daemon while it is stopped (SIGSTOP, 0.3 s), the poller first: as
    under load, when its threads are not scheduled. The poller is then the
    oldest newcomer with bytes waiting, the spot in which it lost its slot
    to half-open sockets at load 12-14 before the fix. Whether it loses it
    still depends on whether its thread runs before the table is full
    (before the fix: 2 runs of 21 failed, load 4-11);
    test_waiting_request_keeps_its_slot shows the case every time."""
    d = daemon(run_for=600)
    stop = threading.Event()
    times, failures, retries = [], [], []

    def polling(c, sent):
        """@p c: a connection whose first request was sent at @p sent."""
        while not stop.is_set():
            t, first, sent = sent or time.monotonic(), sent, None
            try:
                if first is None:
                    c.send(1, fc03(0, 2))
                ok = exception_code(c.receive()) is None
            except Exception as ex:  # noqa: BLE001 - any failure counts
                ok = False
                failures.append(("poll", repr(ex)))
                c = Raw(d.port)
            times.append(time.monotonic() - t)
            if not ok:
                failures.append(("poll", "no answer"))
            time.sleep(0.05)

    def fresh():
        # A new connection for each request. A newcomer that has not yet
        # sent its request can lose its slot to the flood (it looks like
        # any of them); it connects again, as a PLC does, and the time
        # counts from its first attempt.
        while not stop.is_set():
            t = time.monotonic()
            ok = False
            while not ok and time.monotonic() - t < HANG_S:
                try:
                    c = Raw(d.port)
                    ok = exception_code(c.request(1, fc03(0, 2))) is None
                    c.close()
                except (ConnectionError, OSError):
                    retries.append(time.monotonic() - t)
            times.append(time.monotonic() - t)
            if not ok:
                failures.append(("fresh", "no answer"))
            time.sleep(0.1)

    rng = random.Random(12)
    live, kinds = [], {"idle": 0, "half-open": 0, "slowloris": 0}

    def top_up(now):
        """Open hostile sockets until 48 are open (1000 in all)."""
        failed = []
        while sum(kinds.values()) < 1000 and len(live) < 48:
            n, kind = sum(kinds.values()), rng.choice(list(kinds))
            try:
                s = connect_from(f"127.0.1.{1 + n % 250}", d.port)
            except OSError as ex:
                failed.append(repr(ex))
                assert len(failed) < 20, f"20 connects in a row failed: {failed[-3:]}"
                continue
            failed = []
            s.setblocking(False)
            if kind == "half-open":
                s.send(struct.pack(">HHH", n & 0xFFFF, 0, 6)[:5])
            live.append([s, kind, now + rng.uniform(0.2, 1.5), now])
            kinds[kind] += 1

    def trickle(now, close=True):
        """A byte from each slowloris every 80 ms; close those whose time
        is up."""
        for h in list(live):
            s, kind, until, last = h
            if kind == "slowloris" and now - last >= 0.08:
                try:
                    s.send(b"\x00")  # a frame that announced 254 bytes
                except OSError:
                    pass
                h[3] = now
            if close and now >= until:
                s.close()
                live.remove(h)

    # Stopped for 0.3 s: the slowloris sockets have bytes waiting too, and
    # nothing closes, so that the backlog (64) holds all 49.
    os.kill(d.proc.pid, signal.SIGSTOP)
    try:
        poller = Raw(d.port)
        poller.send(1, fc03(0, 2))
        sent = time.monotonic()
        top_up(sent)
        while time.monotonic() < sent + 0.3:
            trickle(time.monotonic(), close=False)
            time.sleep(0.01)
    finally:
        os.kill(d.proc.pid, signal.SIGCONT)
    legit = [threading.Thread(target=polling, args=(poller, sent)),
             threading.Thread(target=fresh)]
    for t in legit:
        t.start()
    t_end = time.monotonic() + 40
    try:
        while (sum(kinds.values()) < 1000 or live) and time.monotonic() < t_end:
            now = time.monotonic()
            top_up(now)
            trickle(now)
            time.sleep(0.01)
    finally:
        for h in live:
            h[0].close()
        time.sleep(0.5)
        stop.set()
        for t in legit:
            t.join(timeout=30)
    srt = sorted(times)
    opened = sum(kinds.values())
    print({"hostile": opened, **kinds, "legit_requests": len(times),
           "p50_s": round(srt[len(srt) // 2], 4), "p99_s": round(srt[int(len(srt) * 0.99)], 4),
           "worst_s": round(srt[-1], 3), "over_1s": sum(1 for x in srt if x >= 1.0),
           "fresh_reconnects": len(retries), "failures": failures[:5]})
    assert opened == 1000 and min(kinds.values()) > 250
    assert not failures, failures[:5]
    assert len(times) > 100
    assert "msg=client-evicted" in d.log()


# ---- O2: the parameter lock ------------------------------------------------

LOCKED = [("mode", 1), ("manual_out", 0.5), ("failsafe_out", -1e9), ("watchdog_ms", 1),
          ("input_sel", 1), ("param_lock", 0), ("param_lock", 1), ("q", 0.5), ("substeps", 5),
          ("commit", 1), ("command", 1), ("command", 2), ("command", 3)]
OPEN = [("e", 0.25), ("sp", 0.1), ("pv", 0.05), ("e_i16", 100), ("tick", 1)]


def test_lock_has_a_holder(daemon):
    """With param_lock, only its holder (the client that set it) can write
    anything but the process inputs and tick: the O2 attack (watchdog_ms 1,
    failsafe_out -1e9 from another client) is refused and the output never
    reads -1e9. The lock ends when its holder writes 0 or disconnects."""
    d = daemon("--clock", "external")
    a, b = Regs(d.client()), Regs(d.client())
    a.write("param_lock", 1)
    for name, value in LOCKED:
        resp = b.write_raw(name, value)
        assert resp.isError() and resp.exception_code == 1, (name, resp)
    for name, value in OPEN:
        b.write(name, value)
    b.tick(50)
    assert b.read("pc") != f32(-1e9) and b.read("watchdog_ms") == 0
    assert b.read("mode") == 0 and b.read("param_lock") == 1
    # the holder may
    a.write("failsafe_out", 0.001)
    a.write("mode", 1)
    a.write("mode", 0)
    a.write("param_lock", 0)
    b.write("mode", 1)  # unlocked: anyone
    b.write("mode", 0)
    a.write("param_lock", 1)
    a.c.close()  # the holder goes: its lock goes with it
    deadline = time.monotonic() + 10 * SLOW
    while b.read("param_lock") != 0:
        assert time.monotonic() < deadline
        time.sleep(0.05)
    b.write("mode", 1)
    assert "reg=param_lock old=1 new=0 result=released-at-disconnect" in d.log()


def test_lock_holder_is_not_evicted(daemon):
    """A flood of connections must not take a lock away by evicting its
    idle holder (its disconnect would release the lock)."""
    d = daemon("--clock", "external", "--max-clients", "2",
               "--first-request-timeout-ms", "100")
    holder = connect_from("127.0.0.1", d.port)
    holder.sendall(adu(1, 1, struct.pack(">BHH", 6, REG["param_lock"][1], 1)))
    assert len(holder.recv(64)) == 12
    time.sleep(0.3)  # the longest idle, past the protection time
    flood = []
    for k in range(20):
        s = connect_from(f"127.0.2.{k + 1}", d.port)
        ask(s)
        flood.append(s)
        time.sleep(0.15)  # each one idle past the protection time in turn
    assert "msg=client-evicted" in d.log()
    assert not re.search(r"msg=client-evicted peer=127\.0\.0\.1:", d.log())
    holder.sendall(adu(2, 1, struct.pack(">BHH", 6, REG["mode"][1], 1)))
    assert len(holder.recv(64)) == 12
    for s in flood:
        s.close()
    time.sleep(0.5)
    other = Regs(d.client())
    assert other.read("param_lock") == 1 and other.read("mode") == 1
    assert other.write_raw("mode", 0).exception_code == 1
    holder.close()


def test_param_lock_flag_locks_everyone(daemon):
    d = daemon("--param-lock", "--clock", "external")
    a, b = Regs(d.client()), Regs(d.client())
    for r in (a, b):
        for name, value in LOCKED:
            resp = r.write_raw(name, value)
            assert resp.isError() and resp.exception_code == 1, (name, resp)
        for name, value in OPEN:
            r.write(name, value)


# ---- O3: per-client staging -------------------------------------------------

def test_staging_is_per_client(daemon):
    """O3: two clients stage partial changes at the same time; each commit
    applies exactly what its client staged, on top of what is committed
    (the other's earlier commit is kept, never reverted, never half
    taken). First one interleaving by hand, then 2 x 150 concurrent
    commits checked through the audit log."""
    d = daemon("--clock", "external")
    a, b = Regs(d.client()), Regs(d.client())
    q0, rc0 = a.read("committed_q"), a.read("committed_RC")
    k0 = a.read("committed_substeps")
    a.write("q", 0.7)
    a.write("substeps", k0 + 5)
    b.write("RC", 0.02)
    # each sees only its own
    assert a.read("RC") == rc0 and b.read("q") == q0 and b.read("substeps") == k0
    a.write("commit", 1)
    assert a.read("committed_q") == f32(0.7) and a.read("committed_RC") == rc0
    assert a.read("committed_substeps") == k0 + 5 and a.read("substeps_used") == k0 + 5
    # b's view: committed + its own RC
    assert b.read("q") == f32(0.7) and b.read("substeps") == k0 + 5
    b.write("commit", 1)
    assert b.read("committed_q") == f32(0.7) and b.read("committed_RC") == f32(0.02)
    assert b.read("committed_substeps") == k0 + 5

    errors = []

    def worker(name, reg, values):
        c = Regs(d.client())
        for v in values:
            try:
                c.write(reg, v)
                c.write("commit", 1)
            except AssertionError as ex:
                errors.append((name, ex))

    qs = [0.5 + 0.001 * i for i in range(150)]
    rcs = [0.01 + 0.0001 * i for i in range(150)]
    ta = threading.Thread(target=worker, args=("a", "q", qs))
    tb = threading.Thread(target=worker, args=("b", "RC", rcs))
    ta.start(), tb.start()
    ta.join(timeout=300), tb.join(timeout=300)
    assert not errors, errors[:3]
    assert a.read("committed_q") == f32(qs[-1]) and a.read("committed_RC") == f32(rcs[-1])
    # Every committed change names one register per commit: q from one
    # client, RC from the other, never both in one commit. (The substeps
    # that a committed with its q above are not part of this count.)
    lines = [l for l in d.log().splitlines()
             if "result=committed" in l and " reg=substeps " not in l]
    by_peer = {}
    for l in lines:
        m = re.search(r"peer=(\S+) .* reg=(\w+) ", l)
        by_peer.setdefault(m.group(1), set()).add(m.group(2))
    mixed = [p for p, regs in by_peer.items() if len(regs) > 1]
    print({"committed_lines": len(lines), "clients": len(by_peer), "mixed": len(mixed)})
    assert not mixed, by_peer
    assert sum(1 for l in lines if " reg=q " in l) >= 150
    assert sum(1 for l in lines if " reg=RC " in l) >= 150


# ---- O4: plausibility ----------------------------------------------------

@pytest.mark.parametrize("gain", [1e9, 1e5])
def test_unstable_set_is_refused(daemon, gain):
    """O4: k1 = k2 = 1e9 (or 1e5) passes every range check, but Example 6's
    loop sampled at 1 kHz (one substep per exchange) is then unstable: the
    commit is refused with exception 03, commit_result 6 and
    commit_err_addr naming k1 (the change that alone makes it so), and the
    running set goes on as if nothing happened."""
    # The reference first: a connection must make its first request within
    # the daemon's first-request timeout (2 s), and the CLI under ASan on a
    # busy machine can take longer than that.
    ref = simulate("--config", "dd", "--fs", "1000", "--duration", "0.05", "--arith", "float")
    d = daemon("--clock", "external", "--substeps", "1")
    r = Regs(d.client())
    r.write("e", 1.0)
    r.write("k1", gain)
    r.write("k2", gain)
    resp = r.write_raw("commit", 1)
    assert resp.isError() and resp.exception_code == 3, resp
    assert r.read("commit_result") == 6
    assert r.read("commit_err_addr") == REG["k1"][1]
    assert r.read("commit_err_param") == 2  # PF_P_K1
    assert r.read("committed_k1") != f32(gain)
    pcs = []
    for _ in range(50):
        r.tick(1)
        pcs.append(r.read("pc"))
    assert max(abs(p - float(row["pc"])) for p, row in zip(pcs, ref)) <= 1e-6
    assert re.search(r"msg=commit-refused .*result=6 param=k1 status=\"unstable sampled loop\"",
                     d.log())


def test_set_beyond_the_rules_rate_is_refused(daemon):
    """O4 with the default substeps (0: the rule's): k1 = k2 = 1e9 makes
    the flapper-bellows loop cross over near 1e10 rad/s, so the rule would
    need about 1e10 Hz inside; capped at 200 kHz the loop is stable but
    rings at +-1.7e11 for a unit step. Refused: exception 03,
    commit_result 8, commit_err_addr on k1 (k2 alone does not restore it,
    so the first of the two changed most), and nothing changes. With
    substeps given, the client chose the rate, and stability at that rate
    is what is checked: the same gains at 200 substeps are accepted."""
    ref = simulate("--config", "dd", "--fs", "20000", "--duration", "0.05")[::20]
    d = daemon("--clock", "external")   # after the reference: the first-request timeout
    r = Regs(d.client())
    r.write("e", 1.0)
    r.write("k1", 1e9)
    r.write("k2", 1e9)
    resp = r.write_raw("commit", 1)
    assert resp.isError() and resp.exception_code == 3, resp
    assert r.read("commit_result") == 8
    assert r.read("commit_err_addr") == REG["k1"][1]
    assert r.read("commit_err_param") == 2  # PF_P_K1
    assert r.read("committed_k1") == f32(0.1) and r.read("substeps_used") == 20
    pcs = []
    for _ in range(50):
        r.tick(1)
        pcs.append(r.read("pc"))
    assert max(abs(p - float(row["pc"])) for p, row in zip(pcs, ref)) <= 1e-6
    assert re.search(r"msg=commit-refused .*result=8 param=k1 status=\"the substep rule's "
                     r"rate is beyond the limits\"", d.log())
    # The staged gains are still this client's; with substeps given they
    # are judged by their stability at 1 kHz x 200.
    r.write("substeps", 200)
    r.write("commit", 1)
    assert r.read("commit_result") == 0
    assert r.read("committed_k1") == f32(1e9) and r.read("substeps_used") == 200


def test_stability_is_judged_at_the_internal_rate(daemon):
    """The check judges the loop that runs, designed at fs x substeps:
    k1 = k2 = 1e5 is stable at 1 kHz x 20 substeps (rho = 1 - 7.6e-8) and
    is accepted; going back to one substep alone makes it unstable
    (rho = 1.0034 at 1 kHz), so that commit is refused and commit_err_addr
    names substeps. The refused change is in the audit."""
    d = daemon("--clock", "external", "--substeps", "20")
    r = Regs(d.client())
    r.write("k1", 1e5)
    r.write("k2", 1e5)
    r.write("commit", 1)
    assert r.read("commit_result") == 0
    assert r.read("committed_k1") == f32(1e5) and r.read("substeps_used") == 20
    r.write("substeps", 1)
    resp = r.write_raw("commit", 1)
    assert resp.isError() and resp.exception_code == 3, resp
    assert r.read("commit_result") == 6
    assert r.read("commit_err_addr") == REG["substeps"][1]
    assert r.read("substeps_used") == 20 and r.read("committed_substeps") == 20
    log = d.log()
    assert re.search(r"msg=commit-refused .*result=6 param=substeps ", log), log
    assert re.search(r"msg=write peer=\S+ role=plain unit=1 reg=substeps old=20 new=1 "
                     r"result=refused", log), log


def test_unstable_config_file_is_refused(conf):
    """One substep: the loop runs at the file's fs, where it is unstable."""
    text = re.sub(r"^k1 = .*$", "k1 = 1e9", conf.read_text(), count=1, flags=re.M)
    text = re.sub(r"^k2 = .*$", "k2 = 1e9", text, count=1, flags=re.M)
    text = re.sub(r"^substeps = .*$", "substeps = 1", text, count=1, flags=re.M)
    conf.write_text(text)
    p = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True, text=True)
    assert p.returncode == 2
    assert "the sampled loop is unstable" in p.stderr and "'k1'" in p.stderr, p.stderr


def test_config_file_beyond_the_rules_rate_is_refused(conf):
    """The default substeps, and gains whose loop the rule cannot follow
    within the limits: refused at --seal-config (and so at start), with
    the reason and what to do."""
    text = re.sub(r"^k1 = .*$", "k1 = 1e9", conf.read_text(), count=1, flags=re.M)
    text = re.sub(r"^k2 = .*$", "k2 = 1e9", text, count=1, flags=re.M)
    conf.write_text(text)
    p = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True, text=True)
    assert p.returncode == 2
    assert ("the substep rule needs an internal rate beyond the limits (10000 substeps, "
            "200000 Hz): 'k1' makes it so; give substeps to choose the rate") in p.stderr, \
        p.stderr


# ---- O5: audit -------------------------------------------------------------

def test_audit_log(daemon):
    """Every write that changes behaviour is logged with the client's
    address, the unit, the register, old and new value and the result;
    refused writes are warnings, at most 10 per 10 s."""
    d = daemon("--clock", "external", "--instances", "2")
    a, b = Regs(d.client(), unit=2), Regs(d.client(), unit=2)
    a.write("mode", 1)
    a.write("failsafe_out", 0.002)
    a.write("q", 0.6)
    a.write("commit", 1)
    a.write("command", 2)
    a.write("param_lock", 1)
    for _ in range(30):
        assert b.write_raw("mode", 0).exception_code == 1
    log = d.log()
    port = r"127\.0\.0\.1:\d+ role=plain unit=2"
    for pat in [rf"msg=write peer={port} reg=mode old=0 new=1 result=ok",
                rf"msg=write peer={port} reg=failsafe_out old=0 new=0\.002\d* result=ok",
                rf"msg=write peer={port} reg=q old=0\.9\d* new=0\.6\d* result=committed",
                rf"msg=commit peer={port} config=dd",
                rf"msg=command peer={port} command=reset result=ok",
                rf"msg=write peer={port} reg=param_lock old=0 new=1 result=ok",
                rf"msg=write-refused peer={port} addr=10 count=1 reg=mode exception=1 "
                r"reason=locked"]:
        assert re.search(pat, log), (pat, log)
    assert log.count("msg=write-refused") == 10


# The request of the tests below: FC03, two holding registers from 0;
# its answer is 13 bytes (MBAP 7, function, byte count, 4 data).
READ_HR = adu(1, 1, fc03(0, 2))
READ_HR_ANSWER = 13


class TlsByHand:
    """A TLS session to daemon @p d over a plain socket, through memory
    BIOs, so that a test can cut one record's bytes on the wire."""

    def __init__(self, d, pki):
        self.sock = socket.create_connection(("127.0.0.1", d.tls_port), timeout=5 * SLOW)
        self.inc, self.out = ssl.MemoryBIO(), ssl.MemoryBIO()
        self.obj = client_ctx(pki, "viewer").wrap_bio(self.inc, self.out)
        while True:
            try:
                self.obj.do_handshake()
                break
            except ssl.SSLWantReadError:
                self.sock.sendall(self.out.read())
                self._more()
        self.sock.sendall(self.out.read())  # the client's Finished

    def _more(self):
        data = self.sock.recv(65536)
        assert data, "closed by the daemon"
        self.inc.write(data)

    def record(self, data):
        """@p data as the bytes of one record on the wire."""
        self.obj.write(data)
        return self.out.read()

    def read(self, n):
        got = b""
        while len(got) < n:
            try:
                got += self.obj.read(n - len(got))
            except ssl.SSLWantReadError:
                self._more()
        return got


def connected(d, request, tls):
    """(a way to send bytes of one request on the wire, to read n bytes of
    its answer, the local port) on a connection to daemon @p d."""
    if tls:
        t = TlsByHand(d, request.getfixturevalue("pki"))
        return t.record, t.sock.sendall, t.read, t.sock.getsockname()[1]
    s = socket.create_connection(("127.0.0.1", d.port), timeout=5 * SLOW)

    def read(n):
        got = b""
        while len(got) < n:
            part = s.recv(n - len(got))
            assert part, "closed by the daemon"
            got += part
        return got
    return (lambda data: data), s.sendall, read, s.getsockname()[1]


@pytest.mark.parametrize("tls", [False, True], ids=["plain", "tls"])
def test_a_request_cut_by_the_deadline_says_so(daemon, request, tls):
    """Part of the first request, then nothing: the connection ends at the
    first-request deadline (the byte gap is far longer), with that reason
    (before: byte-timeout, the wait's own)."""
    args = ("--first-request-timeout-ms", str(int(1000 * SLOW)), "--byte-timeout-ms", "10000",
            "--verbose")
    d = start_tls(daemon, request.getfixturevalue("pki"), *args) if tls else daemon(*args)
    wire, send, _, port = connected(d, request, tls)
    send(wire(READ_HR[:3]))
    assert closed_reason(d, port, 10) == "first-request-timeout", d.log()[-2000:]


SHIM = r"""
#define _GNU_SOURCE
#include <dlfcn.h>
#include <sys/socket.h>
/* SO_RCVLOWAT ignored: poll() says readable at any byte, as Linux does
 * below a capped mark or under memory pressure. */
int setsockopt(int fd, int level, int name, const void *v, socklen_t n)
{
    static int (*real)(int, int, int, const void *, socklen_t);
    if (level == SOL_SOCKET && name == SO_RCVLOWAT)
        return 0;
    if (real == 0)
        real = (int (*)(int, int, int, const void *, socklen_t))dlsym(RTLD_NEXT, "setsockopt");
    return real(fd, level, name, v, n);
}
"""


@pytest.fixture(scope="module")
def no_rcvlowat(tmp_path_factory):
    cc = shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler for the SO_RCVLOWAT shim")
    tmp = tmp_path_factory.mktemp("shim")
    (tmp / "shim.c").write_text(SHIM)
    subprocess.run([cc, "-shared", "-fPIC", "-o", str(tmp / "shim.so"), str(tmp / "shim.c"),
                    "-ldl"], check=True)
    return str(tmp / "shim.so")


@pytest.mark.parametrize("tls", [False, True], ids=["plain", "tls"])
def test_readable_below_the_mark_is_a_wait(daemon, request, tls, no_rcvlowat, monkeypatch):
    """Linux may say a socket is readable while fewer bytes than
    SO_RCVLOWAT have come (the mark is capped at half of tcp_rmem[2]; under
    memory pressure any byte wakes the reader). Readable with no new byte
    and no end of stream is one more wait, not the peer's close: with the
    mark ignored (a shim preloaded into the daemon), a request (TLS: its
    record) cut in two on the wire, the parts 0.3 s apart, is answered
    (before: closed as peer-closed at the first part)."""
    old = os.environ.get("LD_PRELOAD")
    monkeypatch.setenv("LD_PRELOAD", no_rcvlowat + (":" + old if old else ""))
    # the ASan build wants its runtime first; the shim only wraps a call
    monkeypatch.setenv("ASAN_OPTIONS",
                       os.environ.get("ASAN_OPTIONS", "") + ":verify_asan_link_order=0")
    args = ("--byte-timeout-ms", "10000", "--verbose")
    d = start_tls(daemon, request.getfixturevalue("pki"), *args) if tls else daemon(*args)
    if old:     # the rest of the test as it was given (a CI's own preload)
        monkeypatch.setenv("LD_PRELOAD", old)
    else:
        monkeypatch.delenv("LD_PRELOAD")
    wire, send, read, port = connected(d, request, tls)
    data = wire(READ_HR)
    send(data[:3])
    time.sleep(0.3)
    send(data[3:])
    assert read(READ_HR_ANSWER)[:2] == READ_HR[:2], d.log()[-2000:]
    assert closed_reason(d, port, 0) is None


def test_part_of_a_request_then_close_frees_the_slot_at_once(daemon):
    """Part of a request, then the client's close: the daemon ends the
    connection at once as peer-closed, not after the byte gap (10 s here),
    or a flood of such connections would hold the slot table (as the fuzz
    test's did when "readable with no new byte" became a wait)."""
    d = daemon("--byte-timeout-ms", "10000", "--verbose")
    s = socket.create_connection(("127.0.0.1", d.port), timeout=5 * SLOW)
    port = s.getsockname()[1]
    s.sendall(READ_HR[:3])
    time.sleep(0.1)
    s.close()
    assert closed_reason(d, port, 2) == "peer-closed", d.log()[-2000:]


def test_an_urgent_byte_ends_the_connection(daemon):
    """Modbus has no urgent data. A request one of whose bytes the client
    sends as TCP urgent data can never be read whole (every peek and
    FIONREAD stops at the urgent mark): the daemon ends it at once as a bad
    frame, where before the thread woke every 10 ms to the end of the byte
    gap (10 s here)."""
    d = daemon("--byte-timeout-ms", "10000", "--first-request-timeout-ms", "10000",
               "--verbose")
    s = socket.create_connection(("127.0.0.1", d.port), timeout=5 * SLOW)
    port = s.getsockname()[1]
    s.sendall(READ_HR[:3])
    s.send(READ_HR[3:4], socket.MSG_OOB)
    s.sendall(READ_HR[4:])
    assert closed_reason(d, port, 2) == "bad-frame", d.log()[-2000:]
    s.close()
