# SPDX-License-Identifier: MIT
"""The diagnosis as one JSON object, and as a Markdown report with plots."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from . import evidence as ev_mod
from . import model


def _num(v):
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def effect_params_abs(d, fr) -> dict:
    """Effect parameters in the record's own units (saturation limits are
    absolute output values: the fit works on deviations from pc0)."""
    p = {k: _num(v) if k != "dead_time_samples" else int(v)
         for k, v in fr.effect_params.items()}
    if "sat_lo" in p:
        p["sat_lo"] += d.pc0
        p["sat_hi"] += d.pc0
    return p


def _params(d, fr) -> dict:
    out = {g: _num(v) for g, v in fr.groups.items()}
    out.update(effect_params_abs(d, fr))
    return out


def _ci(d, fr) -> dict:
    out = {}
    for name, (lo, hi) in fr.ci.items():
        if name == "nozzle_k":
            name = "nozzle_xh"
            lo, hi = (1 / hi if hi and hi > 0 else None), (1 / lo if lo and lo > 0 else None)
        shift = d.pc0 if name in ("sat_lo", "sat_hi") else 0.0
        out[name] = [None if lo is None else _num(lo + shift),
                     None if hi is None else _num(hi + shift)]
    return out


def _model(d, fr) -> dict:
    return {
        "params": _params(d, fr),
        "ci95": _ci(d, fr),
        "fitted": [("nozzle_xh" if n == "nozzle_k" else n) for n in fr.free]
                  + (["dead_time"] if fr.effect == "dead_time" else []),
        "nrmse_fit": _num(fr.nrmse_fit),
        "nrmse_val": _num(fr.nrmse_val),
        "bic": _num(fr.bic),
    }


def to_dict(d) -> dict:
    ext = d.extended
    return {
        "config": d.config,
        "cause": d.cause,
        "place": model.PLACE[d.cause],
        "effect_params": effect_params_abs(d, ext) if d.cause != "none" else {},
        "baseline": _model(d, d.baseline),
        "extended": _model(d, ext),
        "gain": {
            "nrmse_val_before": _num(d.baseline.nrmse_val),
            "nrmse_val_after": _num(ext.nrmse_val),
            "delta_bic": _num(ext.bic - d.baseline.bic),
        },
        "candidates": [
            {"name": c.effect, "nrmse_val": _num(c.nrmse_val), "bic": _num(c.bic),
             "delta_bic": _num(c.bic - d.baseline.bic), "passes_guards": bool(c.passes),
             "params": effect_params_abs(d, c)}
            for c in d.candidates],
        "evidence": list(d.evidence),
        "verdict": list(d.why),
        "identified": {g: bool(v) for g, v in d.identified.items()},
        "held": dict(d.fixed_reason),
        "record": {"n": d.n, "n_fit": d.nfit, "fs": d.fs, "e0": d.e0, "pc0": d.pc0,
                   "noise_sd": _num(d.noise_sd), "noise_floor_val": _num(d.noise_floor_val),
                   "notes": list(d.record_notes)},
        "elapsed_s": round(d.elapsed, 2),
    }


def to_json(d) -> str:
    return json.dumps(to_dict(d), indent=2, allow_nan=False)


# ----------------------------------------------------------------- report
def write_report(d, out: Path) -> Path:
    from . import plots
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    figs = plots.all_figures(d, out)
    j = to_dict(d)
    L = []
    w = L.append
    w(f"# pneufrac-fit diagnosis: configuration `{d.config}`\n")
    w(f"**Verdict: {d.cause}**" + (f" ({model.PLACE[d.cause]})" if d.cause != "none" else "")
      + "\n")
    for s in d.why:
        w(f"- {s}")
    w("")
    w(f"![overview]({figs['overview']})\n")
    w("## Data\n")
    w(f"- {d.n} samples at {d.fs:g} Hz; fit on the first {d.nfit} "
      f"({d.nfit / d.fs:.3g} s), validation on the last {d.n - d.nfit}.")
    for note in d.record_notes:
        w(f"- {note}")
    w(f"- Estimated sensor noise sd {d.noise_sd:.4g} (output units); noise floor of the "
      f"validation NRMSE {d.noise_floor_val:.4f}.")
    w("- NRMSE = rms(measured - simulated) / sd(measured) on the part named. The model "
      "is simulated from rest over the whole record (output error, not one-step "
      "prediction).\n")
    w("## 1. Baseline: the paper's linear fractional model\n")
    w("Only groups of the paper's parameters reach the output (k1 and k2 act as a "
      "product; a, b, A, ks and Ψmin only through K and L):\n")
    w("| group | meaning | value | 95 % interval | status |")
    w("|---|---|---|---|---|")
    for g in model.CONFIG_GROUPS[d.config]:
        v = d.baseline.groups[g]
        lo, hi = d.baseline.ci.get(g, (None, None))
        ci = (f"[{model.fmt_value(g, lo)}, {model.fmt_value(g, hi)}]"
              if lo is not None and g in d.baseline.free else "-")
        status = "identified" if d.identified.get(g) else d.fixed_reason.get(g, "held")
        w(f"| {g} | {model.GROUPS[g][3]} | {model.fmt_value(g, v)} | {ci} | {status} |")
    w("")
    w(f"NRMSE fit {d.baseline.nrmse_fit:.4f}, validation {d.baseline.nrmse_val:.4f}; "
      f"BIC {d.baseline.bic:.1f} (fit part, k = {d.baseline.k}). Intervals are "
      "s²(JᵀJ)⁻¹ from the output-error Jacobian; with a coloured residual they are "
      "optimistic.\n")
    w("## 2. What the baseline gets wrong\n")
    for s in d.evidence:
        w(f"- {s}")
    w("")
    w(f"![baseline residuals]({figs['before']})\n")
    w("## 3. The cause\n")
    w("Each candidate is the baseline plus one effect block, placed where the physics "
      "puts it, fitted from warm starts (the baseline's values) and fresh starts. "
      f"A candidate must lower BIC by more than {10:g} and the held-out mean-square error "
      "by more than 5 %; the lowest held-out NRMSE among those wins.\n")
    w("| candidate | place | effect parameters | NRMSE val | ΔBIC | passes |")
    w("|---|---|---|---|---|---|")
    for c in sorted(d.candidates, key=lambda c: c.nrmse_val):
        w(f"| {c.effect} | {model.PLACE[c.effect]} | "
          f"{ev_mod.describe_effect(c.effect, effect_params_abs(d, c), d.fs)} | "
          f"{c.nrmse_val:.4f} | {c.bic - d.baseline.bic:+.1f} | {'yes' if c.passes else 'no'} |")
    w("")
    w(f"![candidates]({figs['candidates']})\n")
    w("## 4. Extended model and the gain\n")
    if d.cause == "none":
        w("No effect was added: the baseline stands.\n")
    else:
        w(f"Effect: {ev_mod.describe_effect(d.cause, j['effect_params'], d.fs)}.\n")
        w("| parameter | value | 95 % interval |")
        w("|---|---|---|")
        for name, v in j["extended"]["params"].items():
            if name == "dead_time_samples":
                continue
            lo, hi = j["extended"]["ci95"].get(name, [None, None])
            fmt = (lambda x: model.fmt_value(name, x)) if name in model.GROUPS or name in (
                "lag", "dead_time") else (lambda x: f"{x:.4g}")
            ci = f"[{fmt(lo)}, {fmt(hi)}]" if lo is not None and hi is not None else "-"
            w(f"| {name} | {fmt(v) if v is not None else '-'} | {ci} |")
        w("")
    g = j["gain"]
    w("| | baseline | extended |")
    w("|---|---|---|")
    w(f"| NRMSE fit | {d.baseline.nrmse_fit:.4f} | {d.extended.nrmse_fit:.4f} |")
    w(f"| NRMSE validation | {g['nrmse_val_before']:.4f} | {g['nrmse_val_after']:.4f} |")
    w(f"| BIC | {d.baseline.bic:.1f} | {d.extended.bic:.1f} (Δ {g['delta_bic']:+.1f}) |")
    w("")
    w(f"![extended residuals]({figs['after']})\n")
    (out / "report.md").write_text("\n".join(L) + "\n", encoding="utf-8")
    (out / "diagnosis.json").write_text(to_json(d) + "\n", encoding="utf-8")
    return out / "report.md"
