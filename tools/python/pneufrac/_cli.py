# SPDX-License-Identifier: MIT
"""What the Python programs (pneufrac-fit, pneufrac-reduce) share on their
command lines: a bad argument is one line on stderr, prefixed with the
program's name, and the usage exit status, never a traceback."""

from __future__ import annotations

import argparse
import math
import sys


class UsageError(Exception):
    """A bad argument or input file: the program prints it as one line and
    exits with its usage status."""


def parser_class(program: str, status: int) -> type[argparse.ArgumentParser]:
    """An ArgumentParser (and subparser) class whose errors name @p program
    (not "pneufrac-fit diagnose": the program is what the user typed) and
    exit with @p status."""

    class _Parser(argparse.ArgumentParser):
        def error(self, message):
            print(f"{program}: error: {message}", file=sys.stderr)
            sys.exit(status)

    return _Parser


def finite_number(text: str, what: str) -> float:
    """@p text as a finite float; otherwise a UsageError that names @p what
    (the option, or the option and its whole argument)."""
    try:
        x = float(text)
    except ValueError:
        raise UsageError(f"{what}: '{text}' is not a number") from None
    if not math.isfinite(x):
        raise UsageError(f"{what}: '{text}' is not finite")
    return x
