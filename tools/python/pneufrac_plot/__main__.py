# SPDX-License-Identifier: MIT
"""Entry point of pneufrac-plot (see the package docstring)."""
from __future__ import annotations

import sys

from . import __doc__ as _doc

EXIT_USAGE = 2
EXIT_MISSING = 3
KINDS = ("bode", "step")


def _fail(msg: str, code: int) -> int:
    print(f"pneufrac-plot: {msg}", file=sys.stderr)
    return code


def _read(path: str):
    """The CSV as a structured array, and its '#' lines after the units."""
    import numpy as np
    with open(path, encoding="utf-8") as f:
        notes = [ln[1:].strip() for ln in f if ln.startswith("#")]
    data = np.genfromtxt(path, delimiter=",", names=True, comments="#",
                         dtype=float, encoding="utf-8")
    data = np.atleast_1d(data)
    notes = [n for n in notes if not n.startswith("units:")]
    return data, notes


def _bode(data, notes, path, png):
    from pneufrac import plots
    try:
        fig = plots.bode(data, notes[0] if notes else None)
    except ValueError as e:
        raise ValueError(f"{path}: {e} (a CSV of pneufrac bode?)") from None
    fig.savefig(png, dpi=120)


def _step(data, notes, path, png):
    from pneufrac import plots
    if "t" not in (data.dtype.names or ()) or "pc" not in data.dtype.names:
        raise ValueError(f"{path}: no columns 't' and 'pc' (a CSV of pneufrac step?)")
    exact = data["pc_exact"] if "pc_exact" in data.dtype.names else None
    fig = plots.step(data["t"], data["pc"], exact, notes[0] if notes else None)
    fig.savefig(png, dpi=120)


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else list(argv)
    if args in (["-h"], ["--help"]):
        print(_doc.strip())
        return 0
    if len(args) != 3 or args[0] not in KINDS:
        return _fail("usage: pneufrac-plot {bode,step} CSV PNG", EXIT_USAGE)
    kind, path, png = args
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as e:
        return _fail(f"needs numpy and matplotlib ({e}); pip install matplotlib",
                     EXIT_MISSING)
    try:
        data, notes = _read(path)
        (_bode if kind == "bode" else _step)(data, notes, path, png)
    except (OSError, ValueError) as e:
        return _fail(str(e), EXIT_USAGE)
    return 0


if __name__ == "__main__":
    sys.exit(main())
