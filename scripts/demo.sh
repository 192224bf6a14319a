#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Quick start, command 1: set up, start pneufracd with the paper's Example 6
# (FrDD) on 127.0.0.1 (a free port, lockstep clock so the result is exactly
# reproducible), drive a unit step through it with pymodbus, print the
# response, write build/demo/example6-step.png and .csv, stop the daemon.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
./scripts/setup.sh

mkdir -p build/demo
log=$(mktemp)
# --run-for: the daemon stops by itself even if this script is killed.
./build/port/posix/pneufracd --listen 127.0.0.1:0 --clock external --run-for 600 \
    2>"$log" &
pid=$!
cleanup() {
  kill "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  rm -f "$log"
}
trap cleanup EXIT

port=""
for _ in $(seq 100); do
  port=$(sed -n 's/.*msg=listening addr=[^ ]* port=\([0-9]*\).*/\1/p' "$log")
  [[ -n $port ]] && break
  if ! kill -0 "$pid" 2>/dev/null; then
    cat "$log" >&2
    echo "demo: pneufracd did not start" >&2
    exit 1
  fi
  sleep 0.1
done
if [[ -z $port ]]; then
  cat "$log" >&2
  echo "demo: pneufracd did not start listening" >&2
  exit 1
fi
echo "[demo] pneufracd (pid $pid) listening on 127.0.0.1:$port"

.venv/bin/python port/posix/examples/step_client.py --port "$port" --samples 1000 \
    --plot build/demo/example6-step.png --csv build/demo/example6-step.csv

kill -TERM "$pid"
wait "$pid"
echo "[demo] pneufracd stopped: $(grep -o 'msg=stopped.*' "$log")"
