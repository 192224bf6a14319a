# SPDX-License-Identifier: MIT
"""Figures of pneufrac, as matplotlib Figures: nothing is written and no
window opens. ``fig.savefig("x.png")`` writes one; in Jupyter a Figure
returned by a cell is shown. The Figures are made without pyplot (no
global state, any backend), so a program may make thousands.

The command-line tools draw with these same functions: pneufrac-plot
(`pneufrac bode|step --plot`) and pneufrac-fit's reports.
"""
from __future__ import annotations

from matplotlib.figure import Figure


def _columns(data, names):
    """Columns of a FreqResp, a DataFrame or a structured array (a CSV of
    the C tool read by numpy), by name; ValueError naming a missing one."""
    if hasattr(data, "to_frame"):
        data = data.to_frame()
    have = set(data.columns) if hasattr(data, "columns") else set(data.dtype.names or ())
    missing = [c for c in names if c not in have]
    if missing:
        raise ValueError(f"no column {missing[0]!r}")
    return data


def bode(fr, title: str | None = None) -> Figure:
    """Bode plot of a frequency response: pneufrac.freqresp's result, or a
    table with the columns of `pneufrac bode` (omega, ideal_db, ideal_deg,
    discrete_db, discrete_deg)."""
    cols = ("omega", "ideal_db", "ideal_deg", "discrete_db", "discrete_deg")
    title = title or getattr(fr, "title", "") or "pneufrac bode"
    data = _columns(fr, cols)
    fig = Figure(figsize=(7.5, 6.5))
    mag, ph = fig.subplots(2, 1, sharex=True)
    for ax, key, unit in ((mag, "db", "magnitude (dB)"), (ph, "deg", "phase (degrees)")):
        ax.semilogx(data["omega"], data[f"ideal_{key}"], "k-", lw=1.6,
                    label="ideal (irrational)")
        ax.semilogx(data["omega"], data[f"discrete_{key}"], "C1--", lw=1.4,
                    label="realised at fs")
        ax.set_ylabel(unit)
        ax.grid(True, which="both", alpha=0.3)
    ph.set_xlabel("omega (rad/s)")
    mag.legend(loc="best")
    mag.set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


def step(t, pc, pc_exact=None, title: str | None = None) -> Figure:
    """A step response: the realised p_c against time, with the exact one
    (pneufrac step's pc_exact column) when given."""
    fig = Figure(figsize=(7.5, 4.5))
    ax = fig.subplots()
    ax.plot(t, pc, "C1-", lw=1.4, label="realised (pc)")
    if pc_exact is not None:
        ax.plot(t, pc_exact, "k--", lw=1.2, label="exact (pc_exact)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("p_c (output units)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    ax.set_title(title or "pneufrac step: unit-step response", fontsize=9)
    fig.tight_layout()
    return fig


def fleet_summary(df, title: str = "fleet", top: int = 30) -> Figure:
    """The fleet report's figure, from its table (pneufrac-fit fleet's
    fleet.parquet or fleet.csv read by pandas): how many loops show each
    effect, and the severity of the @top most severe loops."""
    ok = df[df["status"] == "ok"]
    counts = {}
    for causes in ok["causes"]:
        for c in str(causes).split("+"):
            counts[c] = counts.get(c, 0) + 1
    n_bad = int((df["status"] != "ok").sum())
    names = sorted((c for c in counts if c != "none"), key=lambda c: -counts[c])
    names += [c for c in ("none",) if c in counts]
    values = [counts[c] for c in names]
    if n_bad:
        names.append("not diagnosed")
        values.append(n_bad)
    worst = ok[ok["causes"] != "none"].sort_values("severity", ascending=False).head(top)
    fig = Figure(figsize=(11, max(3.5, 0.28 * len(worst) + 1.5)), layout="constrained")
    ax_n, ax_s = fig.subplots(1, 2, width_ratios=[1, 2])
    colours = {c: f"C{i}" for i, c in enumerate(n for n in names
                                                if n not in ("none", "not diagnosed"))}
    colours.update({"none": "0.7", "not diagnosed": "k"})
    ax_n.barh(names[::-1], values[::-1], color=[colours[c] for c in names[::-1]])
    ax_n.set_xlabel("loops")
    ax_n.set_title("loops per named effect", fontsize=10)
    if len(worst):
        first = [str(c).split("+")[0] for c in worst["causes"]]
        ax_s.barh(list(worst["loop"])[::-1], list(worst["severity"])[::-1],
                  color=[colours.get(c, "C7") for c in first[::-1]])
        ax_s.set_xlabel("severity (rms the effects account for / output sd)")
    else:
        ax_s.text(0.5, 0.5, "no loop has a named effect", ha="center", va="center",
                  transform=ax_s.transAxes)
    ax_s.set_title(f"most severe loops (top {top}; colour: first cause)", fontsize=10)
    fig.suptitle(title, fontsize=11)
    return fig
