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


def _need(data, cols, path):
    missing = [c for c in cols if c not in (data.dtype.names or ())]
    if missing:
        raise ValueError(f"{path}: no column {missing[0]!r} (a CSV of pneufrac?)")


def _bode(data, notes, path, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    _need(data, ("omega", "ideal_db", "ideal_deg", "discrete_db", "discrete_deg"), path)
    fig, (mag, ph) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 6.5))
    for ax, key, unit in ((mag, "db", "magnitude (dB)"), (ph, "deg", "phase (degrees)")):
        ax.semilogx(data["omega"], data[f"ideal_{key}"], "k-", lw=1.6,
                    label="ideal (irrational)")
        ax.semilogx(data["omega"], data[f"discrete_{key}"], "C1--", lw=1.4,
                    label="realised at fs")
        ax.set_ylabel(unit)
        ax.grid(True, which="both", alpha=0.3)
    ph.set_xlabel("omega (rad/s)")
    mag.legend(loc="best")
    mag.set_title(notes[0] if notes else "pneufrac bode", fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def _step(data, notes, path, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    _need(data, ("t", "pc"), path)
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    ax.plot(data["t"], data["pc"], "C1-", lw=1.4, label="realised (pc)")
    if "pc_exact" in data.dtype.names:
        ax.plot(data["t"], data["pc_exact"], "k--", lw=1.2, label="exact (pc_exact)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("p_c (output units)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    ax.set_title(notes[0] if notes else "pneufrac step: unit-step response", fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


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
