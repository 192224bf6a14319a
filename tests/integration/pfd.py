# SPDX-License-Identifier: MIT
"""Helpers for the pneufracd integration tests: start the real daemon on a
free loopback port, and address its registers by the names of the
generated register map (so the tests use exactly what docs/ documents)."""

import os
import re
import signal
import struct
import subprocess
import time
from pathlib import Path

from pymodbus.client import ModbusTcpClient

ROOT = Path(__file__).resolve().parents[2]
DAEMON = os.environ.get("PNEUFRACD", str(ROOT / "build/port/posix/pneufracd"))
CLI = os.environ.get("PNEUFRAC_CLI", str(ROOT / "build/tools/pneufrac"))
# Everything a test waits for is bounded; sanitizer builds are slower.
SLOW = float(os.environ.get("PNEUFRAC_TEST_SLOWDOWN", "1"))
# An answer that takes this long means the daemon hangs. Tests check that
# every request is answered, and correctly; how fast is measured (printed
# here, and in bench/), never asserted: the test machine may be loaded.
HANG_S = 5 * SLOW

def wait_until(cond, seconds, what, step=0.01, between=None):
    """Poll cond() until it holds, for at most @seconds (times SLOW);
    between(), if given, runs before each new poll."""
    deadline = time.monotonic() + seconds * SLOW
    while not cond():
        assert time.monotonic() < deadline, f"{what}: not within {seconds * SLOW:g} s"
        if between is not None:
            between()
        time.sleep(step)


F32 = ModbusTcpClient.DATATYPE.FLOAT32
U32 = ModbusTcpClient.DATATYPE.UINT32


def _load_regmap():
    """name -> (space, address, type) from `pneufracd --print-register-map`."""
    out = subprocess.run([DAEMON, "--print-register-map"], check=True,
                         capture_output=True, text=True, timeout=30).stdout
    regs, space = {}, None
    for line in out.splitlines():
        if line.startswith("## Holding"):
            space = "hold"
        elif line.startswith("## Input"):
            space = "input"
        m = re.match(r"\| (\d+)(?:-\d+)? \| `([^`]+)` \| (\w+) \|", line)
        if m and space:
            regs[m.group(2)] = (space, int(m.group(1)), m.group(3))
    return regs


REG = _load_regmap()


def _map_size(space):
    return max(a + (2 if t in ("f32", "u32") else 1) for sp, a, t in REG.values() if sp == space)


# Registers in each space: every address below is mapped.
HOLD_SIZE = _map_size("hold")
INPUT_SIZE = _map_size("input")


class Daemon:
    """pneufracd on 127.0.0.1, port 0 (the kernel picks a free one)."""

    def __init__(self, tmp_path, *args, run_for=300, wait_ready=True, limits=None):
        """@p limits: {resource.RLIMIT_*: soft limit, or (soft, hard)} for
        the daemon. The log then goes through a pipe, so that RLIMIT_FSIZE
        does not bite the log file."""
        self.log_path = Path(tmp_path) / f"pneufracd-{time.monotonic_ns()}.log"
        self.args = [DAEMON, "--listen", "127.0.0.1:0", "--run-for", str(run_for), *args]
        self._log = open(self.log_path, "w")
        self._pump = None
        if limits:
            import resource
            import threading

            def preexec():
                for res, lim in limits.items():
                    if not isinstance(lim, tuple):
                        lim = (lim, resource.getrlimit(res)[1])
                    resource.setrlimit(res, lim)

            self.proc = subprocess.Popen(self.args, stdin=subprocess.DEVNULL,
                                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                         preexec_fn=preexec)

            def pump():
                for line in iter(self.proc.stderr.readline, b""):
                    self._log.write(line.decode(errors="replace"))
                    self._log.flush()

            self._pump = threading.Thread(target=pump, daemon=True)
            self._pump.start()
        else:
            self.proc = subprocess.Popen(self.args, stdin=subprocess.DEVNULL,
                                         stdout=subprocess.DEVNULL, stderr=self._log)
        self.port = None
        if wait_ready:
            self.wait_ready()

    def log(self):
        return self.log_path.read_text()

    def wait_ready(self, timeout=30):
        deadline = time.monotonic() + timeout * SLOW
        while time.monotonic() < deadline:
            m = re.search(r"msg=listening addr=\S+ port=(\d+)", self.log())
            if m:
                self.port = int(m.group(1))
                return
            if self.proc.poll() is not None:
                raise RuntimeError(f"pneufracd exited ({self.proc.returncode}):\n{self.log()}")
            time.sleep(0.02)
        raise RuntimeError(f"pneufracd not ready:\n{self.log()}")

    def client(self, timeout=5):
        c = ModbusTcpClient("127.0.0.1", port=self.port, timeout=timeout * SLOW, retries=0)
        assert c.connect(), "cannot connect"
        return c

    def stop(self, sig=signal.SIGTERM, timeout=20):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=timeout * SLOW)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self._pump is not None:
            self._pump.join(timeout=10)
        self._log.close()
        return self.proc.returncode

    def kill9(self):
        self.proc.kill()
        self.proc.wait()
        self._log.close()


class Regs:
    """Named access to one instance (unit id) through a pymodbus client.
    word_order: pymodbus's name for the daemon's --word-order, "big" for
    abcd (the default), "little" for cdab."""

    def __init__(self, client, unit=1, word_order="big"):
        self.c = client
        self.unit = unit
        self.word_order = word_order

    def _check(self, rr):
        assert not rr.isError(), f"Modbus error: {rr}"
        return rr

    def read(self, name):
        space, addr, typ = REG[name]
        n = 2 if typ in ("f32", "u32") else 1
        fn = self.c.read_holding_registers if space == "hold" else self.c.read_input_registers
        regs = self._check(fn(addr, count=n, device_id=self.unit)).registers
        if typ == "f32":
            return self.c.convert_from_registers(regs, F32, word_order=self.word_order)
        if typ == "u32":
            return self.c.convert_from_registers(regs, U32, word_order=self.word_order)
        if typ == "i16":
            return regs[0] - 65536 if regs[0] >= 32768 else regs[0]
        return regs[0]

    def encode(self, name, value):
        _, _, typ = REG[name]
        if typ == "f32":
            return ModbusTcpClient.convert_to_registers(float(value), F32,
                                                        word_order=self.word_order)
        if typ == "i16":
            return [int(value) & 0xFFFF]
        return [int(value)]

    def write_raw(self, name, value):
        """Write and return the response (may be an exception)."""
        _, addr, _ = REG[name]
        regs = self.encode(name, value)
        if len(regs) == 1:
            return self.c.write_register(addr, regs[0], device_id=self.unit)
        return self.c.write_registers(addr, regs, device_id=self.unit)

    def write(self, name, value):
        return self._check(self.write_raw(name, value))

    def write_many(self, items):
        """Write (name, value) pairs that are contiguous, in one FC16."""
        items = sorted(items, key=lambda kv: REG[kv[0]][1])
        regs, start = [], REG[items[0][0]][1]
        for name, value in items:
            assert REG[name][1] == start + len(regs), f"{name} is not contiguous"
            regs += self.encode(name, value)
        return self.c.write_registers(start, regs, device_id=self.unit)

    def tick(self, n=1):
        self.write("tick", n)


def simulate(*args):
    """`pneufrac simulate ...` as a list of row dicts."""
    out = subprocess.run([CLI, "simulate", *args], check=True, capture_output=True,
                         text=True, timeout=120).stdout.splitlines()
    out = [line for line in out if not line.startswith("#")]  # the units line
    head = out[0].split(",")
    return [dict(zip(head, row.split(","))) for row in out[1:]]


def simulate_exchanges(fs, k, *args, inputs=None, tmp_path=None):
    """What the daemon's exchanges at rate fs with k substeps give:
    `pneufrac simulate` at the internal rate fs*k, each input held for k
    samples, read at every k-th row (docs/pneufracd.md, "Substeps").
    inputs: e at each exchange (default: a unit step), written to a CSV in
    tmp_path at the internal rate."""
    fi = f"{fs * k:.17g}"
    if inputs is not None:
        path = Path(tmp_path) / f"held-{time.monotonic_ns()}.csv"
        path.write_text("t,e\n" + "".join(f"{(n * k + j) / (fs * k):.17g},{e!r}\n"
                                           for n, e in enumerate(inputs) for j in range(k)))
        args = (*args, "--input", str(path))
    return simulate("--fs", fi, *args)[::k]


def f32(x):
    """x rounded to binary32, as a register holds it."""
    return struct.unpack(">f", struct.pack(">f", float(x)))[0]


class Raw:
    """A bare Modbus TCP socket, for requests pymodbus refuses to build."""

    def __init__(self, port, timeout=None):
        """@p timeout: s (times SLOW); None: HANG_S."""
        import socket
        self.s = socket.create_connection(("127.0.0.1", port),
                                          timeout=HANG_S if timeout is None else timeout * SLOW)
        self.tid = 0

    def close(self):
        self.s.close()

    def request(self, unit, pdu):
        """Send one ADU, return the response PDU (function code first)."""
        self.send(unit, pdu)
        return self.receive()

    def send(self, unit, pdu):
        """The first half of request(): send the ADU, do not wait."""
        import struct
        self.tid = (self.tid + 1) & 0xFFFF
        self.s.sendall(struct.pack(">HHHB", self.tid, 0, len(pdu) + 1, unit) + pdu)

    def receive(self):
        """The second half of request(): the response PDU to the last send()."""
        import struct
        head = self._recv(7)
        tid, proto, length, _ = struct.unpack(">HHHB", head)
        assert tid == self.tid and proto == 0
        return self._recv(length - 1)

    def _recv(self, n):
        buf = b""
        while len(buf) < n:
            chunk = self.s.recv(n - len(buf))
            if not chunk:
                raise ConnectionError("closed by pneufracd")
            buf += chunk
        return buf


# Request PDUs built by hand (function code, big-endian fields), for the
# requests pymodbus refuses to build or hides; the counts default to the
# values' own.
def fc03(addr, count):
    return struct.pack(">BHH", 3, addr, count)


def fc04(addr, count):
    return struct.pack(">BHH", 4, addr, count)


def fc06(addr, value):
    return struct.pack(">BHH", 6, addr, value & 0xFFFF)


def fc16(addr, values, count=None, nbytes=None):
    count = len(values) if count is None else count
    nbytes = 2 * len(values) if nbytes is None else nbytes
    return struct.pack(">BHHB", 16, addr, count, nbytes) + b"".join(
        struct.pack(">H", v & 0xFFFF) for v in values)


def fc23(raddr, rcount, waddr, values):
    return struct.pack(">BHHHHB", 23, raddr, rcount, waddr, len(values),
                       2 * len(values)) + b"".join(struct.pack(">H", v & 0xFFFF) for v in values)


def exception_code(pdu):
    """Exception code of a response PDU, or None if it is not an exception."""
    return pdu[1] if pdu[0] & 0x80 else None
