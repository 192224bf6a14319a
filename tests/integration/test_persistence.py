# SPDX-License-Identifier: MIT
"""Persistence: committed parameters survive a restart; a corrupt, partial
or hand-edited (unsealed) file stops the start with a clear message, or
gives the defaults with --config-fallback-defaults; and kill -9 during
commits, 60 times over, always restarts with a whole old or new set."""

import random
import re
import struct
import subprocess
import threading
import time
import zlib

import pytest

from pfd import DAEMON, REG, SLOW, Daemon, Regs

PARAMS = ["fs", "bump_tau", "a", "b", "k1", "k2", "A", "ks", "tau", "pmin", "pmax",
          "beta", "q", "nu", "RC"]


def f32(x):
    return struct.unpack(">f", struct.pack(">f", x))[0]


@pytest.fixture
def conf(tmp_path):
    path = tmp_path / "pneufracd.conf"
    out = subprocess.run([DAEMON, "--print-default-config"], check=True,
                         capture_output=True, text=True).stdout
    path.write_text(out)
    return path


def committed(r):
    return tuple(round(r.read("committed_" + p), 9) for p in PARAMS)


def start_fails(conf, *extra):
    p = subprocess.run([DAEMON, "--config", str(conf), "--listen", "127.0.0.1:0",
                        "--run-for", "5", *extra], capture_output=True, text=True, timeout=60)
    return p.returncode, p.stderr


def test_commit_persists_and_reloads(daemon, conf):
    d = daemon("--config", str(conf))
    r = Regs(d.client())
    r.write("q", 0.8)
    r.write("RC", 0.02)
    r.write("substeps", 7)
    r.write("commit", 1)
    r.write("watchdog_ms", 250)
    r.write("failsafe_out", 0.003)
    text = conf.read_text()
    # The shortest text that reads back as the staged double (the float32
    # 0.8 that came over the wire), not %.17g's 0.80000001192092896.
    assert re.search(r"^q = 0\.800000011920929$", text, re.M), text
    assert re.search(r"^substeps = 7$", text, re.M), text
    assert re.search(r"^checksum = [0-9a-f]{8}$", text.splitlines()[-1])
    assert d.stop() == 0  # clean stop, and the live settings persisted
    assert re.search(r"^watchdog_ms = 250$", conf.read_text(), re.M)

    d2 = daemon("--config", str(conf))
    r2 = Regs(d2.client())
    assert r2.read("committed_q") == f32(0.8)
    assert r2.read("committed_RC") == f32(0.02)
    assert r2.read("committed_substeps") == 7 and r2.read("substeps_used") == 7
    assert r2.read("q") == f32(0.8)  # staged starts as committed
    assert r2.read("watchdog_ms") == 250
    assert r2.read("failsafe_out") == f32(0.003)


def test_corrupt_byte_is_refused(conf):
    text = conf.read_text()
    conf.write_text(re.sub(r"^q = .*$", "q = 0.8", text, count=1, flags=re.M))
    rc, err = start_fails(conf)
    assert rc == 2
    assert re.match(rf"pneufracd: config {re.escape(str(conf))}:\d+: checksum mismatch", err), err
    assert err.count("\n") == 1


@pytest.mark.parametrize("cut", [0.3, 0.7, 0.99])
def test_partial_file_is_refused(conf, cut):
    data = conf.read_bytes()
    conf.write_bytes(data[:int(len(data) * cut)])
    rc, err = start_fails(conf)
    assert rc == 2
    assert err.startswith(f"pneufracd: config {conf}"), err
    assert "truncated" in err or "no checksum line" in err


def test_missing_checksum_and_bad_lines(conf):
    lines = conf.read_text().splitlines(keepends=True)
    conf.write_text("".join(lines[:-1]))
    rc, err = start_fails(conf)
    assert rc == 2 and "no checksum line" in err and "--seal-config" in err
    conf.write_text("".join(lines[:-1]) + "bogus line\n" + lines[-1])
    rc, err = start_fails(conf)
    assert rc == 2 and re.search(r":\d+: expected 'key = value'", err), err


def test_hand_edit_then_seal(daemon, conf):
    text = re.sub(r"^q = .*$", "q = 0.75", conf.read_text(), count=1, flags=re.M)
    conf.write_text(text)
    assert start_fails(conf)[0] == 2
    p = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    r = Regs(daemon("--config", str(conf)).client())
    assert r.read("committed_q") == 0.75


def test_seal_refuses_invalid_values(conf):
    text = conf.read_text()
    conf.write_text(re.sub(r"^q = .*$", "q = 2", text, count=1, flags=re.M))
    p = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True, text=True)
    assert p.returncode == 2
    assert re.match(rf"pneufracd: config {re.escape(str(conf))}:\d+: q = 2 is out of range", p.stderr)
    # pmax < pmin: each value is in range, the set is not.
    conf.write_text(re.sub(r"^pmax = .*$", "pmax = 0.5", text, count=1, flags=re.M))
    p = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True, text=True)
    assert p.returncode == 2
    assert p.stderr.rstrip().endswith("invalid parameter 'pmax'"), p.stderr


def sealed_unchecked(text):
    """@p text with a valid checksum line, whatever its values (what
    --seal-config would refuse to write)."""
    body = "".join(l for l in text.splitlines(keepends=True)
                   if not l.startswith("checksum = "))
    return body + f"checksum = {zlib.crc32(body.encode()):08x}\n"


def test_set_that_cannot_be_designed(daemon, conf):
    """A file whose checksum is right and whose values each are in range,
    but whose set the library refuses (pmin > pmax): without the fallback
    the start fails naming the instance; with it the daemon runs the
    defaults, read-only, and leaves the file exactly as it was."""
    bad = sealed_unchecked(re.sub(r"^pmax = .*$", "pmax = 0.5", conf.read_text(),
                                  count=1, flags=re.M))
    conf.write_text(bad)
    rc, err = start_fails(conf)
    assert rc == 2
    assert re.fullmatch(rf"pneufracd: config {re.escape(str(conf))}:\d+: \[instance 1\]: "
                        r"invalid parameter 'pmax'\n", err), err
    d = daemon("--config", str(conf), "--config-fallback-defaults")
    r = Regs(d.client())
    assert r.read("committed_config") == 1 and r.read("committed_pmax") == r.read("pmax")
    assert re.search(r"msg=config-fallback using=defaults mode=read-only persistence=off "
                     r".*invalid parameter 'pmax'", d.log()), d.log()
    assert r.read("status") & (1 << 5)  # read-only
    assert r.write_raw("commit", 1).exception_code == 1
    assert d.stop() == 0
    assert conf.read_text() == bad
    assert [p.name for p in conf.parent.iterdir() if p.name.startswith(conf.name)] == [conf.name]


def test_fallback_keeps_security_and_instances(daemon, conf):
    """F1: a file with two instances and security settings in [daemon]
    (param_lock, max_clients, allow, loop_budget) is truncated. The
    fallback run must not weaken any of them: it refuses every write
    (read-only, locked). It never rewrites the file, neither on a write
    attempt nor at shutdown, so once the file is repaired both instances
    and every setting are back."""
    text = subprocess.run([DAEMON, "--print-default-config", "--instances", "2"], check=True,
                          capture_output=True, text=True).stdout
    head, rest = text.split("\n[instance 1]", 1)
    conf.write_text(head + "\n[daemon]\nparam_lock = yes\nmax_clients = 4\n"
                    "allow = 127.0.0.1/32\nloop_budget = 30\n\n[instance 1]" + rest)
    p = subprocess.run([DAEMON, "--seal-config", str(conf)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    good = conf.read_bytes()
    conf.write_bytes(good[:len(good) // 2])
    corrupt = conf.read_bytes()

    d = daemon("--config", str(conf), "--config-fallback-defaults")
    r = Regs(d.client())
    st = r.read("status")
    assert st & (1 << 5) and st & (1 << 4), bin(st)  # read-only, locked
    for name, value in [("param_lock", 0), ("mode", 1), ("failsafe_out", -1e9),
                        ("watchdog_ms", 1), ("q", 0.5), ("substeps", 5), ("commit", 1),
                        ("command", 2), ("command", 3)]:
        resp = r.write_raw(name, value)
        assert resp.isError() and resp.exception_code == 1, (name, resp)
    assert r.read("mode") == 0 and r.read("param_lock") == 1
    assert r.read("committed_substeps") == 0
    # The loop budget is a security setting too: not taken from the file,
    # the default (docs/pneufracd.md, "Loop budget").
    assert re.search(r"msg=loop-load .*budget_pct=50 ", d.log()), d.log()
    assert d.stop() == 0
    assert conf.read_bytes() == corrupt  # not rewritten at shutdown either

    conf.write_bytes(good)  # repaired
    d2 = daemon("--config", str(conf))
    assert "max_clients=4" in d2.log() and 'allow="127.0.0.1/32"' in d2.log()
    assert re.search(r"msg=loop-load .*budget_pct=30 ", d2.log()), d2.log()
    c = d2.client()
    for unit in (1, 2):
        r2 = Regs(c, unit)
        assert r2.read("unit_id") == unit and r2.read("param_lock") == 1


def test_commit_not_persisted(daemon, conf):
    """If FILE cannot be written the set still runs, but the commit says
    so: exception 04, commit_result 5, status bits 2 and 11."""
    d = daemon("--config", str(conf))
    r = Regs(d.client())
    before = conf.read_text()
    tmp = conf.parent / (conf.name + ".tmp")
    tmp.mkdir()  # opening FILE.tmp for writing fails
    r.write("q", 0.5)
    resp = r.write_raw("commit", 1)
    assert resp.isError() and resp.exception_code == 4, resp
    assert r.read("committed_q") == 0.5  # switched in regardless
    assert r.read("commit_result") == 5
    st = r.read("status")
    assert st & (1 << 11) and st & (1 << 2), bin(st)
    assert conf.read_text() == before
    assert "msg=persist-failed" in d.log()
    tmp.rmdir()
    r.write("q", 0.6)
    r.write("commit", 1)
    assert r.read("commit_result") == 0
    assert not r.read("status") & ((1 << 11) | (1 << 2))
    assert re.search(r"^q = 0\.6000000238418579$", conf.read_text(), re.M)


def test_fallback_to_defaults(daemon, conf):
    conf.write_bytes(conf.read_bytes()[:100])
    d = daemon("--config", str(conf), "--config-fallback-defaults")
    r = Regs(d.client())
    assert r.read("committed_config") == 1 and r.read("committed_q") == f32(0.9)
    assert "msg=config-fallback" in d.log()
    assert r.read("status") & (1 << 5)
    assert d.stop() == 0
    assert len(conf.read_bytes()) == 100


def test_fallback_on_missing_file(daemon, tmp_path):
    """A missing file is a fallback too: defaults, read-only, and no file
    is created behind the operator's back."""
    path = tmp_path / "none.conf"
    d = daemon("--config", str(path), "--config-fallback-defaults")
    assert Regs(d.client()).write_raw("mode", 1).exception_code == 1
    assert d.stop() == 0
    assert not path.exists()


SET_A = {"q": 0.8, "beta": 0.85, "RC": 0.05, "tau": 0.002, "k2": 0.2}
SET_B = {"q": 0.7, "beta": 0.75, "RC": 0.02, "tau": 0.003, "k2": 0.3}
KEYS = sorted(SET_A)


def staged_payload(r, values):
    """The whole staged block (config .. RCi) with @p values changed."""
    start, end = REG["config"][1], REG["RCi"][1] + 2
    rr = r.c.read_holding_registers(start, count=end - start, device_id=1)
    regs = list(rr.registers)
    for name, v in values.items():
        a = REG[name][1] - start
        regs[a:a + 2] = r.encode(name, v)
    return start, regs


def as_tuple(values):
    return tuple(f32(values[k]) for k in KEYS)


def read_set(r):
    return tuple(r.read("committed_" + k) for k in KEYS)


def test_kill9_during_commits(tmp_path, conf):
    """60 times: start, commit A and B alternately as fast as possible, and
    kill -9 once a random number (2..6) of commits has been acknowledged,
    a random fraction of a commit later. The restart must find a whole
    set: the last acknowledged one or the one in flight; never a mix,
    never a bad file. Counting acknowledgements instead of waiting a random
    time keeps the totals independent of how fast fsync is."""
    rng = random.Random(1234)
    allowed = None  # sets the next start may find
    kills = commits_total = 0
    for it in range(60):
        d = Daemon(tmp_path, "--config", str(conf), "--rt-priority", "0", run_for=120)
        try:
            r = Regs(d.client())
            got = read_set(r)
            if allowed is not None:
                assert got in allowed, (it, got, allowed)
            stop = threading.Event()
            reached = threading.Event()
            target = rng.randint(2, 6)
            state = {"acked": got, "flight": got, "n": 0, "error": None}

            def commit_loop():
                k = 0
                while not stop.is_set():
                    values = (SET_A, SET_B)[k % 2]
                    k += 1
                    try:
                        start, regs = staged_payload(r, values)
                        r.c.write_registers(start, regs, device_id=1)
                        state["flight"] = as_tuple(values)
                        rr = r.c.write_register(REG["commit"][1], 1, device_id=1)
                    except Exception:  # the kill: the connection is gone
                        return
                    if rr.isError():
                        state["error"] = rr
                        reached.set()
                        return
                    state["acked"] = as_tuple(values)
                    state["n"] += 1
                    if state["n"] >= target:
                        reached.set()

            t = threading.Thread(target=commit_loop)
            t.start()
            assert reached.wait(timeout=60 * SLOW), (it, state)
            assert state["error"] is None, (it, state["error"])
            # Land somewhere inside the next commit (or between two).
            time.sleep(rng.uniform(0.0, 0.01) * SLOW)
            d.kill9()
            kills += 1
            stop.set()
            t.join(timeout=30)
            r.c.close()
            allowed = (state["acked"], state["flight"])
            commits_total += state["n"]
        finally:
            if d.proc.poll() is None:
                d.kill9()
    d = Daemon(tmp_path, "--config", str(conf), run_for=60)
    got = read_set(Regs(d.client()))
    assert got in allowed and got in (as_tuple(SET_A), as_tuple(SET_B))
    assert d.stop() == 0
    # At least 2 acknowledged commits per cycle, by construction.
    assert kills >= 50 and commits_total >= 2 * kills, (kills, commits_total)


def test_sigint_persists_last_state(daemon, conf):
    import signal
    d = daemon("--config", str(conf))
    r = Regs(d.client())
    r.write("failsafe_out", 0.0025)
    r.write("mode", 1)
    assert d.stop(sig=signal.SIGINT) == 0
    assert "msg=stopped status=0" in d.log()
    text = conf.read_text()
    # a live float: its own shortest text, 0.0025, not %.9g's 0.00249999994
    assert re.search(r"^failsafe_out = 0\.0025$", text, re.M), text
    assert re.search(r"^mode = 1$", text, re.M)
    r2 = Regs(daemon("--config", str(conf)).client())
    assert r2.read("mode") == 1 and r2.read("failsafe_out") == f32(0.0025)
