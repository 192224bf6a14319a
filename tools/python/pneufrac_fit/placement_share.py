# SPDX-License-Identifier: MIT
"""Simulations shared between saturation's placements.

Saturation is fitted at every placement the library has
(candidates._fit_saturation), from the same starts with the same search.
The placements differ only in what the relay remembers while a limit acts
on it (pf_effects.h); the library counts the samples on which one did
(pf_ctrl_f64.limited). A simulation on which none did is therefore the
same, bit for bit, at every placement. Inside `shared()` such simulations
are kept, and the same simulation at another placement returns the kept
output instead of running again: each placement's search follows the
others' path, simulation for simulation, until a limit acts, and that
common part is simulated once instead of three times. An answer is either
simulated or the identical one, so no fitted value can change."""
from __future__ import annotations

import contextlib
import threading

import numpy as np

MAX_BYTES = 384 * 2 ** 20      # kept inputs and outputs at most; beyond, simulated again

_store = None


class _Store:
    def __init__(self):
        self.runs = {}           # key -> (input, output)
        self.bytes = 0
        self.lock = threading.Lock()   # the Jacobian's columns run in threads (fit.py)

    @staticmethod
    def key(e: np.ndarray, rest: tuple):
        return (e.size, hash(e.tobytes()), rest)

    def get(self, key, e: np.ndarray):
        got = self.runs.get(key)
        # the hash names the input; the input itself decides
        if got is None or not np.array_equal(got[0], e):
            return None
        return got[1].copy()

    def put(self, key, e: np.ndarray, out: np.ndarray) -> None:
        with self.lock:
            if key in self.runs or self.bytes + e.nbytes + out.nbytes > MAX_BYTES:
                return
            self.runs[key] = (e, out.copy())
            self.bytes += e.nbytes + out.nbytes


def active():
    """The store of the innermost `shared()`, or None."""
    return _store


@contextlib.contextmanager
def shared():
    """Simulations without a limit acting are shared between placements
    while this is open (nested: the outer one's store)."""
    global _store
    outer = _store
    if outer is None:
        _store = _Store()
    try:
        yield _store
    finally:
        _store = outer


def run_key(e: np.ndarray, *rest):
    """The store's key of a simulation of input e with everything else it
    depends on in rest (the placement excluded), or None when some part of
    rest cannot be a key."""
    try:
        hash(rest)
    except TypeError:
        return None
    return _Store.key(e, rest)
