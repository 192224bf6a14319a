#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Modbus TCP fuzzer for pneufracd.

Several processes send random and malformed ADUs (random function codes,
addresses and counts with correct framing; wrong MBAP lengths and protocol
ids; truncated frames; garbage; huge counts; oversized frames) over their
own connections, reconnecting whenever the daemon drops them. One process
sends valid frames byte by byte, slowly, and sometimes stops mid-frame. A
separate, well-behaved client reads unit 1 every 20 ms, checks each
answer, and records its response time and the loop's sample counter.

    fuzz_modbus.py --port P [--adus 100000] [--workers 4] [--min-seconds 10]

Prints one JSON line: adus sent, reconnects, monitor requests, failures
(wrong or missing answers), worst and p99 response time (ms), and sample
counters over time.
"""

import argparse
import json
import multiprocessing as mp
import os
import random
import socket
import struct
import time

# Unit 1 is the monitor's: the fuzzers write to unit 2 (and to units that
# do not exist), so that a random commit cannot change the monitored
# instance's sample rate. Both share the one loop thread.
GOOD_UNITS = [2, 2, 2, 0, 3, 255, 247]


def mbap(tid, unit, pdu, length=None, proto=0):
    length = len(pdu) + 1 if length is None else length
    return struct.pack(">HHHB", tid & 0xFFFF, proto, length & 0xFFFF, unit) + pdu


def random_pdu(rng):
    fc = rng.choice([3, 4, 6, 16, 23, 3, 4, 16, rng.randrange(256)])
    addr = rng.choice([rng.randrange(80), rng.randrange(65536), 0, 17, 18, 19, 65535])
    count = rng.choice([rng.randrange(1, 20), 0, 125, 126, 65535, rng.randrange(65536)])
    if fc in (3, 4):
        return struct.pack(">BHH", fc, addr, count)
    if fc == 6:
        return struct.pack(">BHH", fc, addr, rng.choice([0, 1, 2, 65535, rng.randrange(65536)]))
    if fc == 16:
        n = rng.randrange(0, 40)
        nbytes = rng.choice([2 * n, 2 * n, rng.randrange(256)])
        data = bytes(rng.randrange(256) for _ in range(2 * n))
        return struct.pack(">BHHB", fc, addr, rng.choice([n, n, count]), nbytes & 0xFF) + data
    if fc == 23:
        n = rng.randrange(0, 20)
        data = bytes(rng.randrange(256) for _ in range(2 * n))
        return struct.pack(">BHHHHB", fc, rng.randrange(80), count, addr,
                           rng.choice([n, count]), (2 * n) & 0xFF) + data
    return bytes([fc]) + bytes(rng.randrange(256) for _ in range(rng.randrange(0, 30)))


def random_adu(rng, tid):
    kind = rng.random()
    unit = rng.choice(GOOD_UNITS)
    if kind < 0.80:  # framed correctly, content random
        return mbap(tid, unit, random_pdu(rng)), False
    if kind < 0.85:  # wrong MBAP length
        pdu = random_pdu(rng)
        return mbap(tid, unit, pdu, length=len(pdu) + 1 + rng.choice([-3, -1, 1, 5, 200, 60000])), True
    if kind < 0.88:  # wrong protocol id
        return mbap(tid, unit, random_pdu(rng), proto=rng.randrange(1, 65536)), True
    if kind < 0.92:  # truncated
        a = mbap(tid, unit, random_pdu(rng))
        return a[:rng.randrange(1, len(a))], True
    if kind < 0.95:  # oversized: FC16 with 250 data bytes (ADU > 260)
        pdu = struct.pack(">BHHB", 16, 20, 125, 250) + bytes(250)
        return mbap(tid, unit, pdu), True
    return bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300))), True  # garbage


def connect(port):
    s = socket.create_connection(("127.0.0.1", port), timeout=2)
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    # Blocking, so that recv(MSG_DONTWAIT) really does not wait; a send the
    # daemon does not take within 2 s fails (EAGAIN) instead of hanging.
    s.settimeout(None)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_SNDTIMEO, struct.pack("ll", 2, 0))
    return s


def drain(s):
    try:
        while s.recv(65536, socket.MSG_DONTWAIT):
            pass
    except (BlockingIOError, InterruptedError):
        pass


def fuzz_worker(port, seed, quota, min_end, deadline, out):
    os.nice(10)  # background load: the monitor is the one measured
    rng = random.Random(seed)
    sent = reconnects = 0
    s = None
    tid = 0
    while (sent < quota or time.time() < min_end) and time.time() < deadline:
        try:
            if s is None:
                s = connect(port)
                reconnects += 1
            tid += 1
            adu, breaks = random_adu(rng, tid)
            s.sendall(adu)
            sent += 1
            drain(s)
            if breaks and rng.random() < 0.5:
                # Let the daemon see the stall or the garbage, then move on.
                s.close()
                s = None
        except OSError:
            if s is not None:
                s.close()
            s = None
    if s is not None:
        s.close()
    out.put(("fuzz", sent, reconnects))


def slow_worker(port, seed, deadline, out):
    """Valid FC03 frames one byte at a time, 1-4 ms apart; every fifth frame
    stops half-way and waits past the byte timeout."""
    rng = random.Random(seed)
    sent = answered = 0
    s = None
    while time.time() < deadline:
        try:
            if s is None:
                s = connect(port)
            adu = mbap(sent, 1, struct.pack(">BHH", 3, 0, 10))
            stop_at = len(adu) // 2 if sent % 5 == 4 else len(adu)
            for b in adu[:stop_at]:
                s.sendall(bytes([b]))
                time.sleep(rng.uniform(0.001, 0.004))
            sent += 1
            if stop_at < len(adu):
                time.sleep(0.3)  # the daemon drops us after its byte timeout
                s.close()
                s = None
                continue
            s.settimeout(2)
            if len(s.recv(512)) > 0:
                answered += 1
        except OSError:
            if s is not None:
                s.close()
            s = None
    out.put(("slow", sent, answered))


MONITOR_REGS = 30


def recv_exact(s, n):
    buf = b""
    while len(buf) < n:
        chunk = s.recv(n - len(buf))
        if not chunk:
            raise OSError("closed")
        buf += chunk
    return buf


def monitor_answer(s, tid):
    """Read one answer to the monitor's request @p tid and check that it
    is that request's answer: the same transaction id, protocol 0, unit 1,
    FC04 (not an exception), and a byte count of MONITOR_REGS registers.
    @return the sample counter (input registers 20-21), or a string saying
    what was wrong."""
    head = recv_exact(s, 7)
    rtid, proto, length, unit = struct.unpack(">HHHB", head)
    body = recv_exact(s, length - 1) if 2 <= length <= 254 else b""
    want = 2 + 2 * MONITOR_REGS
    if (rtid, proto, length, unit) != (tid, 0, want + 1, 1) or body[:2] != bytes([4, want - 2]):
        return f"wrong answer: tid {rtid}/{tid} proto {proto} len {length} unit {unit} " \
               f"pdu {body[:4].hex()}"
    return struct.unpack(">I", body[2 + 40:2 + 44])[0]


def monitor(port, stop_at, timeout, out):
    """The well-behaved client: FC04 read of 30 input registers, unit 1,
    every 20 ms. Each answer is checked (monitor_answer); one that is
    wrong, or does not come within @p timeout s (a hang, not slowness),
    is a failure. The response times are recorded, for printing only."""
    lat, samples, failures = [], [], []
    s = connect(port)
    s.settimeout(timeout)
    tid = 0
    req = lambda t: mbap(t, 1, struct.pack(">BHH", 4, 0, MONITOR_REGS))  # noqa: E731
    while time.time() < stop_at.value:
        tid = (tid + 1) & 0xFFFF
        t0 = time.perf_counter()
        try:
            s.sendall(req(tid))
            n = monitor_answer(s, tid)
            if isinstance(n, str):
                raise OSError(n)
            lat.append(time.perf_counter() - t0)
            samples.append((time.time(), n))
        except OSError as ex:
            failures.append(repr(ex))
            s.close()
            try:
                s = connect(port)
                s.settimeout(timeout)
            except OSError:
                break
        time.sleep(0.02)
    s.close()
    out.put(("monitor", lat, samples, failures))


def run(port, adus=100000, workers=4, min_seconds=10, max_seconds=300, hang_seconds=5):
    """Fuzz until @p adus are sent and @p min_seconds have passed; the
    monitor calls an answer that takes @p hang_seconds a failure."""
    t0 = time.time()
    min_end, deadline = t0 + min_seconds, t0 + max_seconds
    out = mp.Queue()
    stop_at = mp.Value("d", deadline + 5)
    mon = mp.Process(target=monitor, args=(port, stop_at, hang_seconds, out))
    mon.start()
    time.sleep(0.3)
    procs = [mp.Process(target=fuzz_worker,
                        args=(port, 1000 + i, adus // workers + 1, min_end, deadline, out))
             for i in range(workers)]
    procs.append(mp.Process(target=slow_worker, args=(port, 7, min_end, out)))
    for p in procs:
        p.start()
    results, slow, mon_res = [], None, None
    while len(results) < workers or slow is None:
        item = out.get(timeout=max_seconds + 60)
        if item[0] == "fuzz":
            results.append(item)
        elif item[0] == "slow":
            slow = item
    fuzz_seconds = time.time() - t0
    stop_at.value = time.time()
    mon_res = out.get(timeout=60)
    for p in procs + [mon]:
        p.join(timeout=30)
    _, lat, samples, failures = mon_res
    lat_sorted = sorted(lat)
    return {
        "adus": sum(r[1] for r in results),
        "reconnects": sum(r[2] for r in results),
        "fuzz_seconds": round(fuzz_seconds, 2),
        "slow_frames": slow[1], "slow_answered": slow[2],
        "monitor_requests": len(lat),
        "monitor_failures": len(failures),
        "monitor_failure_reasons": failures[:5],
        "worst_ms": round(1000 * lat_sorted[-1], 3) if lat else None,
        "p99_ms": round(1000 * lat_sorted[int(0.99 * (len(lat) - 1))], 3) if lat else None,
        "samples": samples,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--adus", type=int, default=100000)
    ap.add_argument("--workers", type=int, default=4)
    ap.add_argument("--min-seconds", type=float, default=10)
    a = ap.parse_args()
    r = run(a.port, a.adus, a.workers, a.min_seconds)
    r["samples"] = [r["samples"][0], r["samples"][-1]] if r["samples"] else []
    print(json.dumps(r))


if __name__ == "__main__":
    main()
