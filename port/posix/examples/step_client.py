#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Drive a unit step through pneufracd with pymodbus and show the response.

With the daemon in lockstep (--clock external) each sample is one Modbus
FC23 transaction: write tick = 1, read back the output p_c (holding
registers 62-63, float32 high word first), so the response is exactly
reproducible. With the internal clock the step is written once and p_c is
polled in real time.

    step_client.py --port 1502 [--samples 1000] [--plot step.png] [--csv step.csv]
"""

import argparse
import sys
import time

from pymodbus.client import ModbusTcpClient

# Addresses from docs/register-map.md.
H_E, H_TICK, H_HOLD_PC = 0, 19, 62
I_STATUS, I_SAMPLES, I_VERSION, I_COMMITTED_FS = 15, 20, 30, 38
EXTERNAL_CLOCK = 1 << 6
F32 = ModbusTcpClient.DATATYPE.FLOAT32
U32 = ModbusTcpClient.DATATYPE.UINT32


def check(rr):
    if rr.isError():
        sys.exit(f"step_client: Modbus error: {rr}")
    return rr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int, default=1502)
    ap.add_argument("--unit", type=int, default=1)
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--step", type=float, default=1.0, help="size of the step in e")
    ap.add_argument("--plot", help="write the response as a PNG")
    ap.add_argument("--csv", help="write the response as CSV (t,e,pc)")
    a = ap.parse_args()

    c = ModbusTcpClient(a.host, port=a.port, timeout=5, retries=0)
    if not c.connect():
        sys.exit(f"step_client: cannot connect to {a.host}:{a.port}")
    u = a.unit
    ver = check(c.read_input_registers(I_VERSION, count=4, device_id=u)).registers
    status = check(c.read_input_registers(I_STATUS, count=1, device_id=u)).registers[0]
    fs = c.convert_from_registers(
        check(c.read_input_registers(I_COMMITTED_FS, count=2, device_id=u)).registers, F32)
    lockstep = bool(status & EXTERNAL_CLOCK)
    print(f"pneufracd {ver[0]}.{ver[1]}.{ver[2]} (register map {ver[3]}) at "
          f"{a.host}:{a.port}, unit {u}: fs = {fs:g} Hz, "
          f"{'lockstep (--clock external)' if lockstep else 'real time'}")

    check(c.write_registers(H_E, c.convert_to_registers(a.step, F32), device_id=u))
    t, pc = [], []
    if lockstep:
        for n in range(a.samples):
            rr = check(c.readwrite_registers(read_address=H_HOLD_PC, read_count=2,
                                             write_address=H_TICK, values=[1], device_id=u))
            t.append(n / fs)
            pc.append(c.convert_from_registers(rr.registers, F32))
    else:
        start = c.convert_from_registers(
            check(c.read_input_registers(I_SAMPLES, count=2, device_id=u)).registers, U32)
        t_end = time.monotonic() + a.samples / fs
        while time.monotonic() < t_end:
            rr = check(c.read_input_registers(0, count=22, device_id=u)).registers
            n = c.convert_from_registers(rr[20:22], U32) - start
            t.append(n / fs)
            pc.append(c.convert_from_registers(rr[0:2], F32))
            time.sleep(0.005)
    c.close()

    print(f"\nstep e = {a.step:g} at t = 0; p_c read back over Modbus:\n")
    print("    t [ms]         p_c")
    marks = sorted({i for i in (0, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)
                    if i < len(t)} | {len(t) - 1})
    for i in marks:
        print(f"{1000 * t[i]:10.1f}  {pc[i]:.9g}")
    print(f"\n{len(t)} samples; peak p_c {max(pc):.6g}, final {pc[-1]:.6g}")

    if a.csv:
        with open(a.csv, "w") as f:
            f.write("t,e,pc\n")
            for ti, p in zip(t, pc):
                f.write(f"{ti:.9g},{a.step:.9g},{p:.9g}\n")
        print(f"wrote {a.csv}")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot([1000 * x for x in t], pc, lw=1.5)
        ax.set_xlabel("t [ms]")
        ax.set_ylabel("p_c")
        ax.set_title(f"pneufracd unit {u}: step response over Modbus TCP")
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)
        print(f"wrote {a.plot}")


if __name__ == "__main__":
    main()
