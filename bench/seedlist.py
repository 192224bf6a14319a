# SPDX-License-Identifier: MIT
"""The seed lists the bench sweeps take on their command line: 1, 1-3 or 1,4."""
from __future__ import annotations

import argparse

RANGE_MAX = 10000     # seeds in one range: a typo like 1-100000000 is refused, not run


def seed_list(text: str, top: int = 2 ** 31 - 1) -> list[int]:
    """The seeds of `text`; ValueError names the part that is not a seed range
    within [0, top]."""
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.strip().partition("-")
        try:
            a, b = int(lo), int(hi or lo)
        except ValueError:
            raise ValueError(part) from None
        if not 0 <= a <= b <= top or b - a > RANGE_MAX:
            raise ValueError(part)
        out += range(a, b + 1)
    return out


def seed_arg(text: str) -> list[int]:
    """seed_list as an argparse type: a bad list is a usage error, not a traceback."""
    try:
        return seed_list(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a seed list (1, 1-3, 1,4): {text!r}") from None
