# SPDX-License-Identifier: MIT
"""Figures of the diagnosis, as matplotlib Figures made without pyplot (no
display, no global state; see pneufrac.plots): all_figures writes them for
the report, pneufrac.Diagnosis.figures hands them to Python."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from . import evidence as ev_mod

# The resolution each figure is written at in the report.
DPI = {"overview": 90, "before": 80, "after": 80, "candidates": 80}


def _subplots(*grid, figsize):
    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.subplots(*grid)


def _mark_held(ax, d, t, label: bool = False) -> None:
    """Shade the held-out (validation) blocks."""
    for i, (a, b) in enumerate(d.split.held):
        ax.axvspan(t[a], t[b - 1], color="0.85", lw=0, zorder=0)
        if label and i == 0:
            ax.text(t[a], ax.get_ylim()[1], " held out", va="top", fontsize=8)


def _zoom(d, width: int):
    """A window in the held-out part that holds a few steps."""
    n0 = d.split.held[0][0]
    k, _ = ev_mod.steps(d.e)
    k = k[[any(a + 5 < x < b for a, b in d.split.held) for x in k]] if k.size else k
    a = int(k[0]) - width // 10 if k.size else n0
    a = max(0, min(a, d.n - width))
    return a, min(d.n, a + width)


def overview(d) -> Figure:
    t = d.t - d.t[0]
    y = d.y
    yb = d.baseline.sim
    ye = d.extended.sim
    named = ", ".join(d.causes) if d.causes else "none"
    a, b = _zoom(d, int(min(d.n // 4, 1.0 * d.fs)))
    fig, ax = _subplots(3, 1, figsize=(9, 7.5))
    ax[0].plot(t, y, lw=0.6, color="0.5", label="measured")
    ax[0].plot(t, yb, lw=0.8, color="C3", label="baseline")
    if d.causes:
        ax[0].plot(t, ye, lw=0.8, color="C0", label=f"extended ({named})")
    _mark_held(ax[0], d, t, label=True)
    ax[0].set_ylabel("p_c")
    ax[0].legend(loc="lower left", fontsize=8, ncol=3)
    ax[0].set_title(f"config {d.config}: verdict {named}; validation NRMSE "
                    f"{d.baseline.nrmse_val:.4f} -> {d.extended.nrmse_val:.4f} "
                    f"(noise floor {d.noise_floor_val:.4f})", fontsize=10)
    ax[1].plot(t[a:b], y[a:b], ".", ms=2, color="0.5", label="measured")
    ax[1].plot(t[a:b], yb[a:b], lw=1, color="C3", label="baseline")
    if d.causes:
        ax[1].plot(t[a:b], ye[a:b], lw=1, color="C0", label="extended")
    ax[1].set_ylabel("p_c (zoom)")
    ax2 = ax[1].twinx()
    ax2.step(t[a:b], d.e[a:b], where="post", color="C2", lw=0.7, alpha=0.6)
    ax2.set_ylabel("e", color="C2")
    ax[1].legend(loc="lower left", fontsize=8)
    rb = d.y - d.baseline.sim
    re = d.y - d.extended.sim
    ax[2].plot(t, rb, lw=0.5, color="C3", label="residual, baseline")
    if d.causes:
        ax[2].plot(t, re, lw=0.5, color="C0", label="residual, extended")
    # the noise process's sd (its colour included), from the final residual
    s = float(np.sqrt(d.noise_model.var)) if d.noise_model is not None else d.noise_sd
    ax[2].axhline(2.576 * s, color="k", lw=0.6, ls=":")
    ax[2].axhline(-2.576 * s, color="k", lw=0.6, ls=":", label="±2.58 noise sd")
    _mark_held(ax[2], d, t)
    ax[2].set_xlabel("t (s)")
    ax[2].set_ylabel("residual")
    ax[2].legend(loc="lower left", fontsize=8, ncol=3)
    return fig


def residuals(d, ev: dict, fr, title: str) -> Figure:
    fs = d.fs
    t = d.t - d.t[0]
    fig, ax = _subplots(2, 3, figsize=(12, 6.5))
    fig.suptitle(title, fontsize=11)
    a = ax[0, 0]
    a.plot(t, ev["r"], lw=0.5)
    _mark_held(a, d, t)
    a.set_title("residual vs time")
    a.set_xlabel("t (s)")
    a = ax[0, 1]
    a.bar(ev["lags"][1:], ev["acf"][1:], width=0.8)
    a.axhline(ev["bound"], color="r", ls="--", lw=0.8)
    a.axhline(-ev["bound"], color="r", ls="--", lw=0.8, label="99 % bound")
    a.set_title(f"residual autocorrelation ({ev['acf_out']} lags outside)")
    a.set_xlabel("lag (samples)")
    a.legend(fontsize=8)
    a = ax[0, 2]
    a.bar(ev["clags"], ev["ccf"], width=0.8, color="C1")
    a.axhline(ev["bound"], color="r", ls="--", lw=0.8)
    a.axhline(-ev["bound"], color="r", ls="--", lw=0.8)
    a.set_title("whitened residual – input-step cross-correlation")
    a.set_xlabel("lag (samples; > 0: residual after the step)")
    a = ax[1, 0]
    if ev["amp"]:
        c = [x[0] for x in ev["amp"]]
        m = [x[1] for x in ev["amp"]]
        s = [x[2] / np.sqrt(x[3]) * 2.576 for x in ev["amp"]]
        a.errorbar(c, m, yerr=s, fmt="o-", capsize=3)
    a.axhline(0, color="k", lw=0.6)
    a.set_title("mean residual by input level (settled)")
    a.set_xlabel("e")
    a = ax[1, 1]
    data = [ev["rise"] or [0.0], ev["fall"] or [0.0]]
    a.boxplot(data, tick_labels=["after rising steps", "after falling steps"])
    a.axhline(0, color="k", lw=0.6)
    a.set_title("mean residual per hold, by step direction")
    a = ax[1, 2]
    if ev["early"] is not None:
        off = ev["early"]["offset"]
        j = (np.arange(ev["early"]["measured"].size) - off) / fs * 1e3
        a.plot(j, ev["early"]["measured"], "o", ms=3, color="0.4", label="measured")
        a.plot(j, ev["early"]["model"], "-", color="C3", label="model")
        a.axvline(0, color="k", lw=0.6)
        a.set_title(f"early response (best shift {ev['early']['lag_samples']:+.2f} samples)")
        a.set_xlabel("time after step (ms)")
        a.set_ylabel("Δp_c / Δe (mean over steps)")
        a.legend(fontsize=8)
    return fig


def candidates(d) -> Figure:
    """Held-out NRMSE of every model tried, round by round."""
    rows = [("baseline", d.baseline.nrmse_val, "0.6")]
    for i, r in enumerate(d.rounds):
        for t in sorted(r, key=lambda t: t.model.nrmse_val):
            on = "" if i == 0 else f" (on {t.ref.effect})"
            col = "C0" if t.passes and t.effect in d.causes else ("C2" if t.passes else "C7")
            rows.append((t.effect + on, t.model.nrmse_val, col))
    fig, ax = _subplots(figsize=(7.5, 0.9 + 0.28 * len(rows)))
    names = [r[0] for r in rows][::-1]
    ax.barh(names, [r[1] for r in rows][::-1], color=[r[2] for r in rows][::-1])
    ax.axvline(d.noise_floor_val, color="k", ls="--", lw=0.8, label="noise floor")
    ax.set_xlabel("validation NRMSE (blue: named, green: passes, grey: fails a guard)")
    ax.set_title("models tried (verdict: " + (", ".join(d.causes) or "none") + ")", fontsize=10)
    ax.legend(fontsize=8)
    return fig


def figures(d) -> dict:
    """The report's figures of diagnosis @d: overview, the residual
    evidence before and after, the candidates; {key: Figure}."""
    return {
        "overview": overview(d),
        "before": residuals(d, d.ev_before, d.baseline,
                            "Baseline (paper's linear model): residual evidence"),
        "after": residuals(d, d.ev_after, d.extended,
                           f"After the fix ({', '.join(d.causes)}): residual evidence"
                           if d.causes else "Baseline kept (no cause named): residual evidence"),
        "candidates": candidates(d),
    }


def all_figures(d, out: Path) -> dict:
    """Writes the figures into folder @out; {key: file name}."""
    out = Path(out)
    files = {"overview": "overview.png", "before": "residuals-baseline.png",
             "after": "residuals-extended.png", "candidates": "candidates.png"}
    for key, fig in figures(d).items():
        fig.savefig(out / files[key], dpi=DPI[key])
    return files
