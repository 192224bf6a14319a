# SPDX-License-Identifier: MIT
"""Digests of values, for caches that answer a repeated question with the
first answer: equal digests, equal values.

The digest is of the values, not of their pickle: a pickle of a numpy
scalar refers to its dtype object, which the arrays of a parent process
share and an unpickled copy does not, so the same problem sent to a
worker pickles to other bytes and every cache keyed by a pickle misses in
the workers."""
from __future__ import annotations

import dataclasses
import hashlib
import inspect
import pickle

import numpy as np


def of(*xs) -> bytes:
    """A 20-byte digest of the values xs (arrays by dtype, shape and
    contents; objects by their class and every attribute)."""
    h = hashlib.blake2b(digest_size=20)
    _feed(h, xs)
    return h.digest()


def _feed(h, x, path: frozenset = frozenset()) -> None:
    """Feed x's value to the hash h, tagged by kind so that no two values
    of different kinds feed the same bytes: arrays by dtype, shape and
    contents, numpy scalars as the Python numbers they equal, mappings in
    key order, functions and classes by their names, objects by their
    class and every attribute. An object met again inside itself (path:
    the containers above x) is fed as a back reference: no recursion
    without end."""
    if isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x)
        h.update(b"A" + a.dtype.str.encode() + repr(a.shape).encode())
        h.update(memoryview(a).cast("B"))
    elif isinstance(x, np.generic):
        _feed(h, x.item(), path)
    elif x is None or isinstance(x, (bool, int, float, str, bytes)):
        h.update(b"S" + repr((type(x).__name__, x)).encode())
    elif isinstance(x, type) or inspect.isroutine(x):
        h.update(b"F" + _name_of(x))
    elif id(x) in path:
        h.update(b"R")
    else:
        _feed_container(h, x, path | {id(x)})


def _feed_container(h, x, path: frozenset) -> None:
    if isinstance(x, dict):
        h.update(b"D%d" % len(x))
        for k in sorted(x, key=repr):
            _feed(h, k, path)
            _feed(h, x[k], path)
    elif isinstance(x, (list, tuple)):
        h.update(b"L%d" % len(x))
        for v in x:
            _feed(h, v, path)
    elif isinstance(x, (set, frozenset)):
        h.update(b"E%d" % len(x))
        for v in sorted(x, key=repr):
            _feed(h, v, path)
    elif hasattr(x, "__dict__"):
        h.update(b"O" + _name_of(type(x)))
        _feed(h, vars(x), path)
    elif dataclasses.is_dataclass(x):          # slotted or frozen without a __dict__
        h.update(b"O" + _name_of(type(x)))
        _feed(h, {f.name: getattr(x, f.name) for f in dataclasses.fields(x)}, path)
    else:
        h.update(b"P" + pickle.dumps(x, pickle.HIGHEST_PROTOCOL))


def _name_of(x) -> bytes:
    """module:qualname, length first: two names never run into the bytes
    that follow them."""
    n = f"{getattr(x, '__module__', '')}:{getattr(x, '__qualname__', repr(x))}".encode()
    return b"%d:" % len(n) + n
