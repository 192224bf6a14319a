# SPDX-License-Identifier: MIT
"""The scenario catalogue: named recipes, each turned into one record by a
seed. A recipe fixes the kind of record (rate, length, excitations, noise
models, effects and the ranges their sizes are drawn from); the seed draws
everything else. Effect sizes are relative to the record (dead time and lag
in data samples, dead band in input span, x_half in input amplitude,
saturation limits as a fraction of the excursion on that side); they
are resolved into absolute values, in pneufrac-fit's units, by make.py.

Classes:
  clean      no effect: every configuration, easy and realistic records,
             drift, a sweep, 10 kHz, jittered time stamps, an input
             that never rests
  easy       1 kHz, 20 s, random steps, white noise 0.5 %, parameters near
             the paper's, one clearly material effect
  realistic  one material effect and what real records bring: coloured
             noise, 12-bit ADC, non-step inputs, operating point away from
             zero, 5 or 20 s records (the *-real recipes); or one such
             feature at a time on an easy record: a nozzle off its
             inflection, 10 kHz, a sine sweep with AR(1) noise
  two        two effects at once
  marginal   one effect sized near the detection limit: `expected` says
             so; `none` or the right cause are both defensible answers
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .controller import CONFIGS
from .excitation import KINDS

SEED_MAX = 2 ** 31 - 1
BY_SEED = None      # config drawn from the seed: CONFIGS[seed % 4]

EASY = dict(cls="easy", spread="near", fs=1000.0, durations=(20.0,), excitations=("steps",),
            noises=("white",), noise_frac=(0.005, 0.005), e_noise_frac=0.0, adc=False,
            jitter=(0.0,), drift_frac=0.0, op="zero", expected="fair")
REAL = dict(cls="realistic", spread="wide", fs=1000.0, durations=(5.0, 20.0),
            excitations=KINDS, noises=("ar1", "pink"), noise_frac=(0.002, 0.01),
            e_noise_frac=0.001, adc=True, jitter=(0.0,), drift_frac=0.0, op="random",
            expected="fair")

# Effect size ranges (see the module docstring for the units).
MATERIAL = {"dead_time": {"samples": (2.0, 15.0)},
            "lag": {"samples": (5.0, 30.0)},
            "saturation": {"frac": (0.6, 0.9)},
            "backlash": {"span_frac": (0.01, 0.05)},
            "nozzle": {"amp_multiple": (1.5, 4.0), "u0": "inflection"}}
MARGINAL = {"dead_time": {"samples": (0.5, 1.5)},
            "lag": {"samples": (1.0, 4.0)},
            "saturation": {"frac": (0.9, 0.97)},
            "backlash": {"span_frac": (0.003, 0.01)},
            "nozzle": {"amp_multiple": (4.0, 7.0), "u0": "inflection"}}
OFF_BIAS = dict(MATERIAL["nozzle"], u0="off")


@dataclass(frozen=True)
class Recipe:
    name: str
    description: str
    config: str | None
    effects: dict
    base: dict = field(default_factory=dict)
    over: dict = field(default_factory=dict)

    def get(self, key: str):
        return self.over.get(key, self.base[key])


def _r(name, desc, config, effects, base, **over) -> Recipe:
    return Recipe(name, desc, config, effects, base, over)


def _catalogue() -> list[Recipe]:
    c = []
    for cfg in CONFIGS:
        c.append(_r(f"clean-{cfg}-steps", f"{cfg}, no effect, easy record", cfg, {}, EASY,
                    cls="clean"))
    for cfg in CONFIGS:
        c.append(_r(f"clean-{cfg}-real", f"{cfg}, no effect, realistic record", cfg, {}, REAL,
                    cls="clean"))
    c += [
        _r("clean-drift", "no effect, steps, white noise, slow drift of 3-6 % of the output "
           "span on p_c", BY_SEED, {}, EASY, cls="clean", drift_frac=(0.03, 0.06)),
        _r("clean-sweep", "no effect, 0.1-5 Hz sine sweep from the first sample (no rest)",
           BY_SEED, {}, EASY, cls="clean", excitations=("sweep",)),
        _r("clean-10khz", "no effect, 10 kHz, 5 s, steps or PRBS",
           BY_SEED, {}, EASY, cls="clean", fs=10000.0, durations=(5.0,),
           excitations=("steps", "prbs")),
        _r("clean-jitter", "no effect, realistic record whose time stamps jitter (sd 0.5 % of "
           "the period, written in microseconds)", BY_SEED, {}, REAL, cls="clean",
           jitter=(0.005,)),
        _r("clean-never-rest", "no effect, an input that never rests; the record opens "
           "mid-operation", BY_SEED, {}, REAL, cls="clean", excitations=("never_rest",)),
    ]
    for eff in ("dead_time", "lag", "saturation", "backlash", "nozzle"):
        c.append(_r(f"{eff}-steps", f"{eff}, material, easy record", BY_SEED,
                    {eff: MATERIAL[eff]}, EASY))
    for eff in ("dead_time", "lag", "saturation", "backlash"):
        c.append(_r(f"{eff}-real", f"{eff}, material, realistic record", BY_SEED,
                    {eff: MATERIAL[eff]}, REAL))
    c += [
        _r("nozzle-offbias", "nozzle biased away from its inflection (u0 in 0.25-0.4 or "
           "0.85-1.3), steps or ramps, white noise", BY_SEED, {"nozzle": OFF_BIAS}, EASY,
           cls="realistic", excitations=("steps", "ramps")),
        _r("nozzle-real", "nozzle off its inflection, realistic record", BY_SEED,
           {"nozzle": OFF_BIAS}, REAL),
        _r("dead_time-10khz", "dead time 2-20 samples at 10 kHz (with a sub-sample part), 5 s",
           BY_SEED, {"dead_time": {"samples": (2.0, 20.0)}}, EASY, cls="realistic",
           fs=10000.0, durations=(5.0,), excitations=("steps", "prbs")),
        _r("lag-jitter", "lag, realistic record with jittered time stamps", BY_SEED,
           {"lag": MATERIAL["lag"]}, REAL, jitter=(0.005,)),
        _r("saturation-wind", "saturation whose relay memory winds on at the limits (the "
           "stop holds the stroke, the diaphragm stays loaded), steps, white noise", BY_SEED,
           {"saturation": dict(MATERIAL["saturation"], stop="wind")}, EASY, cls="realistic"),
        _r("lag-sweep", "lag with a 0.1-5 Hz sine sweep, AR(1) noise", BY_SEED,
           {"lag": MATERIAL["lag"]}, EASY, cls="realistic", excitations=("sweep",),
           noises=("ar1",)),
    ]
    for a, b in (("lag", "backlash"), ("dead_time", "saturation"), ("nozzle", "lag"),
                 ("backlash", "saturation")):
        c.append(_r(f"two-{a}-{b}", f"{a} and {b} at once, material", BY_SEED,
                    {a: MATERIAL[a], b: MATERIAL[b]}, REAL, cls="two"))
    for eff in ("dead_time", "lag", "saturation", "backlash", "nozzle"):
        c.append(_r(f"marginal-{eff}", f"{eff} near the detection limit, easy record",
                    BY_SEED, {eff: MARGINAL[eff]}, EASY, cls="marginal",
                    expected="at the limit"))
    names = [r.name for r in c]
    assert len(set(names)) == len(names)
    return c


CATALOGUE = {r.name: r for r in _catalogue()}


def config_for(recipe: Recipe, seed: int) -> str:
    return recipe.config if recipe.config is not None else CONFIGS[seed % len(CONFIGS)]
