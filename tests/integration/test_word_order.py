# SPDX-License-Identifier: MIT
"""--word-order: every 32-bit register (f32 and u32), read and written, in
the order the daemon was told, checked with pymodbus in both orders and
with mbpoll, whose default word order is cdab (-B selects abcd)."""

import re
import struct
import subprocess

import pytest

from pfd import DAEMON, REG, Regs, wait_until


def words(value, order):
    """The two registers of binary32 @p value, by hand: high word first
    for abcd, low word first for cdab."""
    hi, lo = struct.unpack(">HH", struct.pack(">f", value))
    return [hi, lo] if order == "abcd" else [lo, hi]


PYMODBUS = {"abcd": "big", "cdab": "little"}


@pytest.mark.parametrize("order", ["abcd", "cdab"])
def test_floats_and_counters_in_the_configured_order(daemon, order):
    d = daemon("--clock", "external", "--word-order", order)
    c = d.client()
    r = Regs(c, word_order=PYMODBUS[order])
    wrong = Regs(c, word_order=PYMODBUS["cdab" if order == "abcd" else "abcd"])

    # A write packed by hand in this order is e = 0.5 ...
    assert not c.write_registers(REG["e"][1], words(0.5, order), device_id=1).isError()
    assert r.read("e") == 0.5
    raw = c.read_holding_registers(REG["e"][1], count=2, device_id=1).registers
    assert raw == words(0.5, order)
    # ... and pymodbus, told the same order, reads and writes it alike.
    r.write("q", 0.75)
    r.write("commit", 1)
    assert r.read("committed_q") == 0.75
    assert wrong.read("committed_q") != 0.75
    r.tick(3)
    assert r.read("samples") == 3  # u32: 3 in the low word
    assert wrong.read("samples") == 3 << 16
    assert r.read("e_used") == 0.5
    assert r.read("pc") > 0 and r.read("hold_pc") == r.read("pc")
    # The other order reads other bits: a staged q written so is refused
    # (its bits are out of range), and nothing changed.
    assert wrong.write_raw("q", 0.8).isError()
    assert r.read("q") == 0.75


def test_word_order_from_the_config_file(daemon, tmp_path):
    """The [daemon] key word_order, and the command line over it."""
    conf = tmp_path / "wo.conf"
    text = subprocess.run([DAEMON, "--print-default-config"], check=True, capture_output=True,
                          text=True, timeout=30).stdout
    body = text.split("checksum = ")[0]
    conf.write_text(body.replace("\n[instance 1]", "\n[daemon]\nword_order = cdab\n\n[instance 1]", 1))
    subprocess.run([DAEMON, "--seal-config", str(conf)], check=True, capture_output=True,
                   timeout=30)
    d = daemon("--config", str(conf))
    assert Regs(d.client(), word_order="little").read("committed_fs") == 1000.0
    assert d.stop() == 0
    assert re.search(r"^word_order = cdab$", conf.read_text(), re.M)
    d = daemon("--config", str(conf), "--word-order", "abcd")
    assert Regs(d.client(), word_order="big").read("committed_fs") == 1000.0


def mbpoll(port, *args, write=None):
    """One mbpoll call (one request) against unit 1; @p write: the value
    to write, which mbpoll takes after the host."""
    return subprocess.run(["mbpoll", "-m", "tcp", "-p", str(port), "-a", "1", "-0", "-1", *args,
                           "127.0.0.1", *([] if write is None else [write])],
                          capture_output=True, text=True, timeout=30)


def values(out):
    return {int(m.group(1)): m.group(2) for m in re.finditer(r"^\[(\d+)\]:\s+(\S+)", out, re.M)}


def test_mbpoll_reads_cdab_without_B(daemon):
    d = daemon("--word-order", "cdab")
    r = Regs(d.client(), word_order="little")
    p = mbpoll(d.port, "-t", "4:float", "-r", str(REG["e"][1]), write="0.25")
    assert p.returncode == 0, p.stdout + p.stderr
    assert r.read("e") == 0.25
    p = mbpoll(d.port, "-t", "3:float", "-r", str(REG["committed_q"][1]))
    assert p.returncode == 0, p.stdout + p.stderr
    assert float(values(p.stdout)[REG["committed_q"][1]]) == pytest.approx(0.9, rel=1e-6)
    wait_until(lambda: r.read("samples") > 10, 10, "samples")
    p = mbpoll(d.port, "-t", "3:int", "-r", str(REG["samples"][1]))
    assert p.returncode == 0, p.stdout + p.stderr
    assert 10 < int(values(p.stdout)[REG["samples"][1]]) <= r.read("samples")
    # With -B mbpoll reads abcd: the wrong order for this daemon.
    p = mbpoll(d.port, "-t", "3:float", "-B", "-r", str(REG["committed_q"][1]))
    assert float(values(p.stdout)[REG["committed_q"][1]]) != pytest.approx(0.9, rel=1e-3)
