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
import sys

import numpy as np


def of(*xs) -> bytes:
    """A 20-byte digest of the values xs (arrays by dtype, shape and
    contents; objects by their class and every attribute)."""
    h = hashlib.blake2b(digest_size=20)
    _feed(h, xs)
    return h.digest()


# The kinds of value a module constant holds (numbers, names, tables of
# them, numpy arrays and scalars: pickle writes their contents, so an
# array changed in place changes the digest); a module, class or function
# bound to an upper-case name is not a setting
_PLAIN = (bool, int, float, str, bytes, tuple, list, dict, set, frozenset,
          np.ndarray, np.generic)


def settings(package: str) -> bytes:
    """A 20-byte digest of the settings of every module of `package` loaded
    in this process: each public upper-case name (a leading underscore
    marks a module's own state: its caches) bound to a plain value (a
    number, a name, a table of them: search and fit iteration counts,
    tolerances, model.F_SIM_MIN, the groups' ranges), by its value. A
    cached answer keyed by it is not given to a question asked after any
    of them changed at run time. All of the package's, not a list of what
    one computation reads: a list is missed when the code reads one more,
    and a setting it does not read only costs a repeat made again.

    Of their pickle, not of digest.of's walk (ten times the time, and a
    fit asks for this each time): a module's constants in a forked worker
    are the parent's objects, and pickle the same, so a worker finds what
    its parent cached."""
    h = hashlib.blake2b(digest_size=20)
    for name in _modules_of(package):
        m = sys.modules.get(name)
        if m is None:
            continue
        own = sorted((k, v) for k, v in list(vars(m).items())
                     if k.isupper() and k[0] != "_" and isinstance(v, _PLAIN))
        h.update(pickle.dumps((name, own), pickle.HIGHEST_PROTOCOL))
    return h.digest()


def _modules_of(package: str) -> list:
    """The names of package's loaded modules, sorted; looked for again only
    when a module was loaded or unloaded (a third of settings' time is the
    search of the process's thousand modules). Their count and the last
    loaded name tell: one module unloaded and another loaded leaves the
    count as it was, not the last name."""
    try:
        last = next(reversed(sys.modules), None)
    except RuntimeError:        # another thread loading a module meanwhile
        last = object()         # (equal to nothing: the list is made again)
    n = (len(sys.modules), last)
    got = _MODULES.get(package)
    if got is None or got[0] != n:
        pre = package + "."
        got = (n, sorted(m for m in list(sys.modules) if m == package or m.startswith(pre)))
        _MODULES[package] = got
    return got[1]


_MODULES: dict = {}


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
