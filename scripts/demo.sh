#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Quick start, command 1: set up, then run the paper's Example 6 (FrDD) and
# print a short summary; the full response is written to example6.csv.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
./scripts/setup.sh
./build/tools/pneufrac demo --out example6.csv
