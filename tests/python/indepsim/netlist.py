# SPDX-License-Identifier: MIT
"""A block diagram as a list of named signals, closed into one continuous-
time state space.

Every signal is defined once: as an external input, as a weighted sum of
other signals (a static junction), or as the output of a SISO dynamic block
with diagonal modes (diffusive.Modes scaled by a gain). All algebraic loops
(the relay's, the flapper's) are solved at once by one linear solve, so the
closed loop has no artificial delay and no per-sample iteration.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .diffusive import Modes


@dataclass
class StateSpace:
    """dx/dt = A x + B u, y = C x + D u (continuous time)."""
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    inputs: list[str]
    outputs: list[str]


@dataclass
class Net:
    inputs: list[str]
    _sums: dict[str, dict[str, float]] = field(default_factory=dict)
    _blocks: dict[str, tuple[str, Modes, float]] = field(default_factory=dict)

    def _new(self, name: str) -> None:
        if name in self.inputs or name in self._sums or name in self._blocks:
            raise ValueError(f"signal {name} defined twice")

    def junction(self, out: str, terms: dict[str, float]) -> None:
        """out = sum of gain * signal."""
        self._new(out)
        self._sums[out] = dict(terms)

    def block(self, out: str, inp: str, modes: Modes, gain: float = 1.0) -> None:
        """out = gain * (modes.gain + sum c_k / (s + xi_k)) inp."""
        self._new(out)
        self._blocks[out] = (inp, modes, gain)

    def close(self, outputs: list[str]) -> StateSpace:
        names = list(self._sums) + list(self._blocks)
        idx = {n: i for i, n in enumerate(names)}
        uidx = {n: i for i, n in enumerate(self.inputs)}
        ns = sum(len(m.xi) for _, m, _ in self._blocks.values())
        nsig, nu = len(names), len(self.inputs)
        M = np.zeros((nsig, nsig))   # signal <- signal
        Px = np.zeros((nsig, ns))    # signal <- state
        Pu = np.zeros((nsig, nu))    # signal <- input
        A = np.zeros((ns, ns))
        Bsig = np.zeros((ns, nsig))  # state derivative <- signal
        Bin = np.zeros((ns, nu))     # state derivative <- input

        def wire(row: int, src: str, g: float) -> None:
            if src in uidx:
                Pu[row, uidx[src]] += g
            elif src in idx:
                M[row, idx[src]] += g
            else:
                raise ValueError(f"signal {src} is not defined")

        for out, terms in self._sums.items():
            for src, g in terms.items():
                wire(idx[out], src, g)
        k = 0
        for out, (inp, m, g) in self._blocks.items():
            n = len(m.xi)
            sl = slice(k, k + n)
            A[sl, sl] = -np.diag(m.xi)
            if inp in uidx:
                Bin[sl, uidx[inp]] = 1.0
            elif inp in idx:
                Bsig[sl, idx[inp]] = 1.0
            else:
                raise ValueError(f"signal {inp} is not defined")
            Px[idx[out], sl] = g * m.c
            if m.gain:
                wire(idx[out], inp, g * m.gain)
            k += n
        # signals = M signals + Px x + Pu u  ->  (I - M) signals = Px x + Pu u
        lhs = np.eye(nsig) - M
        if np.linalg.cond(lhs) > 1e12:
            raise ValueError("algebraic loop is singular")
        Sx = np.linalg.solve(lhs, Px)
        Su = np.linalg.solve(lhs, Pu)
        rows = [idx[o] if o in idx else None for o in outputs]
        if None in rows:
            raise ValueError("unknown output")
        return StateSpace(A + Bsig @ Sx, Bsig @ Su + Bin, Sx[rows], Su[rows],
                          list(self.inputs), list(outputs))
