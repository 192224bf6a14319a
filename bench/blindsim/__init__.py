# SPDX-License-Identifier: MIT
"""blindsim: a third, blind simulator of the paper's pneumatic controllers.

Written from the paper's equations (eqs. 9-21, Examples 4, 6, 7) and the
user-facing parts of docs/analysis.md only, to judge `pneufrac-fit
diagnose` from outside. It shares no code and no numerical choice with
pneufrac or its test generators:

- fractional integrals by quadrature of their diffusive representation
  (fracop.py), not a pole-zero fit such as Oustaloup's;
- the closed loop stepped at 20x (1 kHz data) or 5x (10 kHz data) the data
  rate, every operator integrated exactly for an input that is linear
  between steps (first-order hold);
- effects where the physics puts them (plant.py): a play in the
  flapper-nozzle linkage, a nozzle whose back pressure follows compressible
  flow through two orifices (nozzle.py), the relay diaphragm against its
  stops, a pneumatic line with its own lag and transport delay;
- a DAQ that samples at jittered instants and adds AR(2), 1/f or drifting
  sensor noise and an ADC (sensors.py).

`python -m blindsim list|make` (run with bench/ on PYTHONPATH) writes a
record as CSV plus its truth as JSON (catalogue.py).
"""
