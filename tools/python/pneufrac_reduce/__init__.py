# SPDX-License-Identifier: MIT
"""pneufrac-reduce: a linear pneufrac controller (the library's full
design, read through ctypes) reduced on the host to the fewest states that
keep its step response within a requested accuracy over a requested
horizon, realised as a bank of parallel sections (lib pf_bank.h) and
exported as a C header for firmware.

- reduce: the rule (full design, balanced reduction, step-response check);
- balance: balanced truncation and residualisation (scipy);
- realise: the bank form in double, its step response and double run;
- fixed: normalisation and the Q15 and float coefficient sets;
- export: the C header and the JSON record;
- cli: the `pneufrac-reduce` command.
"""
