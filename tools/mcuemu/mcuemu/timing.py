# SPDX-License-Identifier: MIT
"""Cycle estimates from executed instructions, at zero wait states.

Sources (the per-instruction tables; nothing here models caches, flash
wait states, interrupts or bus contention):
- Cortex-M0+: Arm Cortex-M0+ Technical Reference Manual r0p1 (DDI 0484C),
  section 3.3, Table 3-1 "Cortex-M0+ instruction summary". The multiplier
  is taken as the single-cycle option (MULS = 1; the small option costs 32),
  which is what M0+ parts with a DSP-style workload ship with.
- Cortex-M4: Arm Cortex-M4 Processor Technical Reference Manual r0p1
  (DDI 0439B), section 3.3, Table 3-1 "Cortex-M4 instruction set summary",
  its load/store timing notes (section 3.3.2), and section 7.2.3, Table 7-1
  "FPU instruction set" for the single-precision FPU.

Choices the tables leave open, stated so that the figures can be redone:
- M4 pipeline refill P (taken branches, writes to PC): the TRM gives 1 to 3;
  P_M4 = 2 here. Profiles report taken branches, so another P is a
  correction of (P - 2) per taken branch.
- M4 load pipelining (TRM 3.3.2): a single LDR/STR right after a single
  LDR costs one cycle less, unless its address uses that LDR's result; a
  load or store whose address register was written by the instruction
  just before costs one more; STR with an immediate offset costs 1.
- IT costs 1 (the TRM allows folding it into the previous instruction).
  Instructions in an IT block whose condition fails are counted as
  executed, at their full cost (an upper bound).
- SDIV/UDIV cost 12, the TRM's upper bound (the step paths do not divide).
"""
from __future__ import annotations

from dataclasses import dataclass

import capstone
from capstone import arm_const as A

P_M4 = 2

_LOADS = {A.ARM_INS_LDR, A.ARM_INS_LDRB, A.ARM_INS_LDRH, A.ARM_INS_LDRSB, A.ARM_INS_LDRSH}
_STORES = {A.ARM_INS_STR, A.ARM_INS_STRB, A.ARM_INS_STRH}
_MULTI = {A.ARM_INS_LDM, A.ARM_INS_LDMDB, A.ARM_INS_STM, A.ARM_INS_STMDB,
          A.ARM_INS_PUSH, A.ARM_INS_POP}
_FP_MAC = {A.ARM_INS_VMLA, A.ARM_INS_VMLS, A.ARM_INS_VNMLA, A.ARM_INS_VNMLS,
           A.ARM_INS_VFMA, A.ARM_INS_VFMS, A.ARM_INS_VFNMA, A.ARM_INS_VFNMS}
_FP_LONG = {A.ARM_INS_VDIV, A.ARM_INS_VSQRT}
_FP_MULTI = {A.ARM_INS_VLDMIA, A.ARM_INS_VLDMDB, A.ARM_INS_VSTMIA, A.ARM_INS_VSTMDB,
             A.ARM_INS_VPUSH, A.ARM_INS_VPOP}
_FP_MEM = {A.ARM_INS_VLDR, A.ARM_INS_VSTR}
_BARRIERS = {A.ARM_INS_DMB, A.ARM_INS_DSB, A.ARM_INS_ISB}
_SPECIAL = {A.ARM_INS_MRS, A.ARM_INS_MSR}
_DIV = {A.ARM_INS_SDIV, A.ARM_INS_UDIV}
_TABLE_BRANCH = {A.ARM_INS_TBB, A.ARM_INS_TBH}
_DOUBLE_MEM = {A.ARM_INS_LDRD, A.ARM_INS_STRD}


@dataclass(frozen=True)
class Insn:
    """One decoded instruction and its cost on a core."""
    address: int
    size: int
    text: str
    base: int          # cycles when it does not branch (or always, if not a branch)
    taken: int         # cycles when it branches
    branch: bool       # writes the PC
    conditional: bool  # a branch that may fall through


def _mem_regs(insn) -> set[int]:
    regs = set()
    for op in insn.operands:
        if op.type == A.ARM_OP_MEM:
            regs.update(r for r in (op.mem.base, op.mem.index) if r)
    return regs


def _writes_pc(insn) -> bool:
    return A.ARM_REG_PC in insn.regs_access()[1] or insn.id in (
        A.ARM_INS_B, A.ARM_INS_BL, A.ARM_INS_BX, A.ARM_INS_BLX, A.ARM_INS_CBZ,
        A.ARM_INS_CBNZ) or insn.id in _TABLE_BRANCH


def _nregs(insn) -> int:
    return sum(1 for op in insn.operands if op.type == A.ARM_OP_REG) - (
        1 if insn.id in (A.ARM_INS_LDM, A.ARM_INS_LDMDB, A.ARM_INS_STM, A.ARM_INS_STMDB,
                         A.ARM_INS_VLDMIA, A.ARM_INS_VLDMDB, A.ARM_INS_VSTMIA,
                         A.ARM_INS_VSTMDB) else 0)


# ARMv6-M, the M0+ instruction set (DDI 0484C section 3.3): the 16-bit
# Thumb instructions without CBZ, CBNZ and IT, and six 32-bit ones.
# (Capstone names some encodings apart: MOVS Rd, Rm is LSLS #0, NEGS is RSBS.)
_ARMV6M = {getattr(A, f"ARM_INS_{n}") for n in (
    "ADC ADD ADR AND ASR B BIC BKPT BL BLX BX CMN CMP CPS DMB DSB EOR ISB LDM LDR "
    "LDRB LDRH LDRSB LDRSH LSL LSR MOV MOVS MRS MSR MUL MVN NOP ORR POP PUSH REV REV16 "
    "REVSH ROR RSB SBC SEV STM STR STRB STRH SUB SVC SXTB SXTH TST UDF UXTB UXTH "
    "WFE WFI YIELD").split()} | {getattr(A, "ARM_INS_NEG", A.ARM_INS_RSB)}
_ARMV6M_32BIT = {A.ARM_INS_BL, A.ARM_INS_DMB, A.ARM_INS_DSB, A.ARM_INS_ISB, A.ARM_INS_MRS,
                 A.ARM_INS_MSR}


class NotArmv6m(ValueError):
    """An instruction an M0+ cannot execute."""


def _cost_m0plus(insn, prev) -> tuple[int, int]:
    """(base, taken) on a Cortex-M0+ (DDI 0484C Table 3-1). Refuses what
    ARMv6-M lacks: the emulator's M-class model runs any Thumb-2 code, so
    this is where an M0+ image is held to its instruction set."""
    i = insn.id
    if i not in _ARMV6M or (insn.size == 4 and i not in _ARMV6M_32BIT):
        raise NotArmv6m(f"{insn.address:#x}: {insn.mnemonic} {insn.op_str} is not ARMv6-M")
    if i in _LOADS or i in _STORES:
        return 2, 2
    if i in _MULTI:
        n = _nregs(insn)
        if i == A.ARM_INS_POP and A.ARM_REG_PC in insn.regs_access()[1]:
            return 3 + (n - 1), 3 + (n - 1)   # POP {..., PC}: 3 + N, N without PC
        return 1 + n, 1 + n
    if i == A.ARM_INS_BL:
        return 3, 3
    if i in (A.ARM_INS_BX, A.ARM_INS_BLX):
        return 2, 2
    if i == A.ARM_INS_B:
        return (1, 2) if insn.cc != A.ARM_CC_AL else (2, 2)
    if _writes_pc(insn):              # MOV PC, Rm / ADD PC, PC, Rm
        return 2, 2
    if i in _BARRIERS or i in _SPECIAL:
        return 3, 3
    return 1, 1                       # data processing, MULS, extends, hints


def _cost_m4(insn, prev) -> tuple[int, int]:
    """(base, taken) on a Cortex-M4 (DDI 0439B Tables 3-1 and 7-1)."""
    i, P = insn.id, P_M4
    addr_stall = 0
    if prev is not None and (i in _LOADS or i in _STORES or i in _DOUBLE_MEM or i in _MULTI
                             or i in _FP_MEM or i in _FP_MULTI):
        written = set(prev.regs_access()[1])
        prev_is_load = prev.id in _LOADS
        if not prev_is_load and _mem_regs(insn) & written:
            addr_stall = 1            # address from the instruction just before
    pipelined = (prev is not None and prev.id in _LOADS and (i in _LOADS or i in _STORES)
                 and not (_mem_regs(insn) & set(prev.regs_access()[1])))
    if A.ARM_REG_PC in insn.regs_access()[1] and (i in _LOADS or i in _MULTI):
        n = _nregs(insn) if i in _MULTI else 1
        c = (2 if i in _LOADS else 1 + n) + P + addr_stall
        return c, c
    if i in _LOADS:
        c = (1 if pipelined else 2) + addr_stall
        return c, c
    if i in _STORES:
        imm = not any(op.type == A.ARM_OP_MEM and op.mem.index for op in insn.operands)
        c = (1 if imm or pipelined else 2) + addr_stall
        return c, c
    if i in _DOUBLE_MEM:
        return 3 + addr_stall, 3 + addr_stall
    if i in _MULTI:
        c = 1 + _nregs(insn) + addr_stall
        return c, c
    if i in _FP_MEM:
        c = (2 if insn.operands[0].reg >= A.ARM_REG_S0 else 3) + addr_stall
        return c, c
    if i in _FP_MULTI:
        c = 1 + _nregs(insn) + addr_stall
        return c, c
    if i in _FP_MAC:
        return 3, 3
    if i in _FP_LONG:
        return 14, 14
    if i == A.ARM_INS_VMOV and sum(1 for op in insn.operands if op.type == A.ARM_OP_REG) == 4:
        return 2, 2                   # two core registers <-> two singles
    if i in _DIV:
        return 12, 12
    if i in _TABLE_BRANCH:
        return 2 + P, 2 + P
    if _writes_pc(insn):
        conditional = insn.cc != A.ARM_CC_AL or i in (A.ARM_INS_CBZ, A.ARM_INS_CBNZ)
        return (1, 1 + P) if conditional else (1 + P, 1 + P)
    if i in _BARRIERS:
        return 1 + P, 1 + P
    if i in _SPECIAL:
        return 2, 2
    return 1, 1                       # data processing, 32-bit and DSP multiplies, IT, VFP 1-cycle


_COST = {"m0plus": _cost_m0plus, "m4": _cost_m4}


class Decoder:
    """Decodes and prices executed blocks of Thumb code, with a cache."""

    def __init__(self, core: str):
        self._cost = _COST[core]
        self._md = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
        self._md.detail = True
        self._cache: dict[tuple[int, int], list[Insn]] = {}

    def block(self, address: int, code: bytes) -> list[Insn]:
        key = (address, len(code))
        got = self._cache.get(key)
        if got is not None:
            return got
        out, prev, end = [], None, address
        for insn in self._md.disasm(code, address):
            base, taken = self._cost(insn, prev)
            branch = _writes_pc(insn)
            cond = branch and (insn.cc != A.ARM_CC_AL or insn.id in (A.ARM_INS_CBZ, A.ARM_INS_CBNZ))
            out.append(Insn(insn.address, insn.size, f"{insn.mnemonic} {insn.op_str}",
                            base, taken if branch else base, branch, cond))
            prev, end = insn, insn.address + insn.size
        if end != address + len(code):
            raise ValueError(f"undecodable code in block at {address:#x}")
        self._cache[key] = out
        return out
