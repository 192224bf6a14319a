# SPDX-License-Identifier: MIT
"""Plots of the data "pneufrac reproduce" and the accuracy benchmark write.

    .venv/bin/python tools/reproduce/plot.py DIR

Reads the CSVs in DIR and writes a PNG beside each one that is present:
  fig8_ex4.csv, fig9_ex6.csv, fig10_ex7.csv -> step responses (linear and
      log time, float and Q15 over the exact response) with an error panel
  freq_oustaloup.csv -> magnitude and phase of the approximants of s^beta,
      s^q, s^nu against the ideal
  accuracy_grid.csv (bench_accuracy --grid) -> error against cost
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only; no display on a build machine
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TITLES = {
    "fig8_ex4": "Fig. 8: Example 4 (eq. 17), beta x q",
    "fig9_ex6": "Fig. 9: Example 6 (eq. 18, FrDD)",
    "fig10_ex7": "Fig. 10: Example 7 (eq. 20, FrID)",
}


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:]])
    return {h: data[:, i] for i, h in enumerate(head)}, head


def cases_of(head):
    return [h[: -len("_exact")] for h in head if h.endswith("_exact")]


def plot_steps(path, stem):
    col, head = read(path)
    t = col["t"]
    cases = cases_of(head)
    fig, ax = plt.subplots(3, 1, figsize=(9, 11))
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(cases)))
    for c, color in zip(cases, colors):
        ex, fl, q = col[c + "_exact"], col[c + "_float"], col[c + "_q15"]
        peak = np.max(np.abs(ex))
        for a in ax[:2]:
            a.plot(t, ex, color=color, lw=2.5, alpha=0.35)
            a.plot(t, fl, color=color, lw=1, label=c)
            a.plot(t, q, color=color, lw=1, ls=":")
        ax[2].loglog(t, np.abs(fl - ex) / peak + 1e-12, color=color, lw=1)
        ax[2].loglog(t, np.abs(q - ex) / peak + 1e-12, color=color, lw=1, ls=":")
        tb = c + "_toolbox"
        if tb in col:
            for a in ax[:2]:
                a.plot(t, col[tb], color="red", lw=1, ls="--",
                       label=c + ": toolbox band [1e-3, 1e3], N = 5")
            ax[2].loglog(t, np.abs(col[tb] - ex) / peak + 1e-12, color="red",
                         lw=1, ls="--")
    ax[0].set_xlabel("t (s)")
    ax[1].set_xscale("log")
    ax[1].set_xlabel("t (s), log")
    for a in ax[:2]:
        a.set_ylabel("p_c for a unit step in e")
        a.grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=7, ncol=2)
    ax[0].set_title(TITLES.get(stem, stem) + "\nthick pale: exact (inverse Laplace); "
                    "solid: float; dotted: Q15 (simulated at pneufrac reproduce "
                    "--fs, default 100 kHz)", fontsize=9)
    ax[2].set_xlabel("t (s), log")
    ax[2].set_ylabel("|error| / peak")
    ax[2].set_ylim(1e-7, 1)
    ax[2].grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(os.path.dirname(path), stem + ".png"), dpi=90)
    plt.close(fig)


def plot_freq(path):
    col, _ = read(path)
    w = col["w"]
    fig, ax = plt.subplots(2, 3, figsize=(13, 7), sharex=True)
    for k, (name, order) in enumerate((("beta", 0.8), ("q", 0.9), ("nu", 0.94))):
        for kind, style in (("ideal", "k-"), ("oustaloup", "b-"), ("refined", "g--")):
            ax[0, k].semilogx(w, col[f"{name}_{kind}_db"], style, lw=1, label=kind)
            ax[1, k].semilogx(w, col[f"{name}_{kind}_deg"], style, lw=1)
        ax[0, k].set_title(f"s^{order} ({name}), 20 kHz, default band")
        for a in ax[:, k]:
            a.axvspan(1e-3, np.pi * 20000, color="0.9", zorder=0)
            a.grid(True, which="both", alpha=0.3)
        ax[1, k].set_xlabel("omega (rad/s); grey: band [1e-3, pi fs]")
    ax[0, 0].set_ylabel("magnitude (dB)")
    ax[1, 0].set_ylabel("phase (deg)")
    ax[0, 0].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(os.path.dirname(path), "freq_oustaloup.png"), dpi=90)
    plt.close(fig)


def plot_cost(path):
    """Worst error over the cases against sections per operator (2N+1)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.5), sharey=True)
    rates = sorted({float(r["fs"]) for r in rows})
    bands = list(dict.fromkeys(r["band"] for r in rows))
    styles = {"double": "-", "float": "--", "q15": ":"}
    for i, fs in enumerate(rates):
        for b, color in zip(bands, ("red", "blue", "green")):
            for arith, ls in styles.items():
                pts = {}
                for r in rows:
                    if float(r["fs"]) == fs and r["band"] == b and r["arith"] == arith:
                        e = float(r["error"])
                        n = int(r["N"])
                        if e >= 0:
                            pts[n] = max(pts.get(n, 0.0), e)
                ns = sorted(pts)
                if ns:
                    ax[i].semilogy([2 * n + 1 for n in ns], [100 * pts[n] for n in ns],
                                   color=color, ls=ls, marker="o",
                                   label=f"{b}, {arith}")
        ax[i].set_title(f"fs = {fs / 1000:g} kHz")
        ax[i].set_xlabel("sections per operator (2N+1)")
        ax[i].grid(True, which="both", alpha=0.3)
    ax[0].set_ylabel("worst max |error| over the cases (% of peak)")
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(os.path.dirname(path), "accuracy_cost.png"), dpi=90)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot.py DIR")
    d = sys.argv[1]
    done = []
    for stem in TITLES:
        p = os.path.join(d, stem + ".csv")
        if os.path.exists(p):
            plot_steps(p, stem)
            done.append(stem + ".png")
    p = os.path.join(d, "freq_oustaloup.csv")
    if os.path.exists(p):
        plot_freq(p)
        done.append("freq_oustaloup.png")
    p = os.path.join(d, "accuracy_grid.csv")
    if os.path.exists(p):
        plot_cost(p)
        done.append("accuracy_cost.png")
    if not done:
        sys.exit(f"plot.py: no known CSV in {d}")
    print("[reproduce] wrote " + ", ".join(os.path.join(d, x) for x in done),
          file=sys.stderr)


if __name__ == "__main__":
    main()
