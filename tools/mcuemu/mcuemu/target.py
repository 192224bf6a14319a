# SPDX-License-Identifier: MIT
"""A linked Cortex-M image in Unicorn, called the way firmware calls it.

Memory map: the image's own (port/cortex-m/example.ld: flash at
0x08000000, RAM at 0x20000000 with the stack at its top), plus a scratch
region at 0x60000000 (external RAM on a real part) for instances and the
long input/output buffers, and a return stub. Calls follow the AAPCS:
r0-r3, and s0 for a float argument or result (hard-float ABI on the M4).
"""
from __future__ import annotations

import bisect
import struct
from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np
from elftools.elf.elffile import ELFFile
from unicorn import UC_ARCH_ARM, UC_MODE_MCLASS, UC_MODE_THUMB, UC_HOOK_BLOCK, Uc
from unicorn import arm_const as U

from .timing import Decoder

FLASH, FLASH_SIZE = 0x08000000, 0x00100000
RAM, RAM_SIZE = 0x20000000, 0x00010000
SCRATCH, SCRATCH_SIZE = 0x60000000, 0x01000000
STOP = FLASH + FLASH_SIZE - 0x100      # return address of every call: a BKPT
STACK_TOP = RAM + 0x2000                # _estack of example.ld (8 KB of RAM)
# Seconds one call may run before it counts as hung (a timer, not an
# instruction count: counting would hook every instruction).
CALL_TIMEOUT = 600

MODELS = {"m0plus": U.UC_CPU_ARM_CORTEX_M0, "m4": U.UC_CPU_ARM_CORTEX_M4}


@dataclass
class Profile:
    """What the calls made inside Target.counting() executed.

    edges[(block, size, successor)] = how often the block ran and then
    control went to successor (a block address, or STOP at the return)."""
    edges: dict = field(default_factory=lambda: defaultdict(int))
    calls: int = 0


@dataclass
class Cost:
    instructions: int
    cycles: int
    taken_branches: int
    by_function: dict  # name -> (instructions, cycles)


class Target:
    def __init__(self, elf_path: str, core: str):
        self.core = core
        self.elf_path = elf_path
        with open(elf_path, "rb") as f:
            elf = ELFFile(f)
            segments = [(s["p_vaddr"], s.data(), s["p_memsz"]) for s in elf.iter_segments()
                        if s["p_type"] == "PT_LOAD"]
            symtab = elf.get_section_by_name(".symtab")
            self.symbols = {s.name: s["st_value"] for s in symtab.iter_symbols() if s.name}
            # One name per address; of aliases (libgcc's __aeabi_lmul is
            # __muldi3) the EABI name, which is what the code calls.
            names: dict[int, str] = {}
            for s in symtab.iter_symbols():
                if s["st_info"]["type"] == "STT_FUNC":
                    a = s["st_value"] & ~1
                    if a not in names or s.name.startswith("__aeabi"):
                        names[a] = s.name
        self._func_addr = sorted(names)
        self._func_name = [names[a] for a in self._func_addr]
        self.uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
        self.uc.ctl_set_cpu_model(MODELS[core])
        self.uc.mem_map(FLASH, FLASH_SIZE)
        self.uc.mem_map(RAM, RAM_SIZE)
        self.uc.mem_map(SCRATCH, SCRATCH_SIZE)
        for vaddr, data, memsz in segments:
            self.uc.mem_write(vaddr, data + bytes(memsz - len(data)))
        self.uc.mem_write(STOP, b"\x00\xbe")    # BKPT #0: never reached
        self._brk = SCRATCH
        self._profile: Profile | None = None
        self._prev = None
        self._decoder = Decoder(core)
        self._hook = None

    # ---- memory ----
    def alloc(self, nbytes: int, align: int = 8) -> int:
        addr = (self._brk + align - 1) // align * align
        if addr + nbytes > SCRATCH + SCRATCH_SIZE:
            raise MemoryError("scratch region exhausted")
        self._brk = addr + nbytes
        self.uc.mem_write(addr, bytes(nbytes))
        return addr

    def free_to(self, addr: int) -> None:
        """Releases everything allocated at or after addr (a stack)."""
        self._brk = addr

    def write_array(self, addr: int, a: np.ndarray) -> None:
        self.uc.mem_write(addr, np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<")).tobytes())

    def read_array(self, addr: int, n: int, dtype) -> np.ndarray:
        dt = np.dtype(dtype).newbyteorder("<")
        return np.frombuffer(bytes(self.uc.mem_read(addr, n * dt.itemsize)), dtype=dt).astype(dtype)

    def read_u32(self, addr: int) -> int:
        return struct.unpack("<I", self.uc.mem_read(addr, 4))[0]

    # ---- calls ----
    def call(self, name: str, *args: int, s0: float | None = None) -> tuple[int, float]:
        """Calls a function with integer/pointer arguments (and a float in
        s0); returns (r0, s0) as left by the callee."""
        regs = (U.UC_ARM_REG_R0, U.UC_ARM_REG_R1, U.UC_ARM_REG_R2, U.UC_ARM_REG_R3)
        if len(args) > len(regs):
            raise ValueError("at most four integer arguments")
        for r, v in zip(regs, args):
            self.uc.reg_write(r, int(v) & 0xFFFFFFFF)
        if s0 is not None:
            self.uc.reg_write(U.UC_ARM_REG_S0, struct.unpack("<I", struct.pack("<f", s0))[0])
        self.uc.reg_write(U.UC_ARM_REG_SP, STACK_TOP)
        self.uc.reg_write(U.UC_ARM_REG_LR, STOP | 1)
        self._prev = None
        self.uc.emu_start(self.symbols[name] | 1, STOP, timeout=CALL_TIMEOUT * 1000000)
        pc = self.uc.reg_read(U.UC_ARM_REG_PC)
        if pc != STOP:
            raise RuntimeError(f"{name} stopped at {pc:#x}, not at its return")
        if self._profile is not None:
            if self._prev is not None:
                self._profile.edges[self._prev + (STOP,)] += 1
            self._profile.calls += 1
        r0 = self.uc.reg_read(U.UC_ARM_REG_R0)
        f = struct.unpack("<f", struct.pack("<I", self.uc.reg_read(U.UC_ARM_REG_S0)))[0]
        return r0, f

    # ---- counting ----
    def _on_block(self, uc, address, size, _):
        prev = self._prev
        if prev is not None:
            self._profile.edges[prev + (address,)] += 1
        self._prev = (address, size)

    def start_counting(self) -> Profile:
        """Counts every block executed by the calls that follow, until
        stop_counting(); a block hook, so the emulator runs at close to
        full speed in between."""
        self._profile = Profile()
        self._hook = self.uc.hook_add(UC_HOOK_BLOCK, self._on_block)
        return self._profile

    def stop_counting(self) -> None:
        self.uc.hook_del(self._hook)
        self._hook = None
        self._profile = None

    def function_of(self, address: int) -> str:
        i = bisect.bisect_right(self._func_addr, address) - 1
        return self._func_name[i] if i >= 0 else "?"

    def cost(self, profile: Profile) -> Cost:
        """Instructions and estimated cycles of a profile (timing.py)."""
        instructions = cycles = taken = 0
        by_function: dict[str, list[int]] = defaultdict(lambda: [0, 0])
        for (address, size, successor), n in profile.edges.items():
            block = self._decoder.block(address, bytes(self.uc.mem_read(address, size)))
            c = sum(i.base for i in block[:-1])
            last = block[-1]
            branched = successor != address + size
            if last.conditional:
                c += last.taken if branched else last.base
                taken += n if branched else 0
            else:
                c += last.base
                taken += n if last.branch else 0
            instructions += n * len(block)
            cycles += n * c
            f = by_function[self.function_of(address)]
            f[0] += n * len(block)
            f[1] += n * c
        return Cost(instructions, cycles, taken, {k: tuple(v) for k, v in by_function.items()})
