#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Regenerates the paper's figures: sets up (scripts/setup.sh), writes the
# CSVs with "pneufrac reproduce" and draws the PNGs with matplotlib from
# the venv. See docs/paper.md for what they show.
#   scripts/reproduce.sh [DIR]      default DIR: docs/figures
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

out=${1:-docs/figures}
./scripts/setup.sh >&2
mkdir -p "$out"
./build/tools/pneufrac reproduce --out "$out"
.venv/bin/python tools/reproduce/plot.py "$out"
