#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# shellcheck disable=SC2317  # the step_* functions are called through run_step
#
# Sets up (scripts/setup.sh), then runs every check. A failing step does not
# stop the later ones; the exit status is non-zero if any step failed.
#   ctest     unit and reference tests of the Release build in build/
#   asan      the same tests built with ASan + UBSan in build-asan/
#   lint      cppcheck over lib/, tools/ and port/
#   firmware  cross builds for Cortex-M0+/M4 and their symbol rules
#   target    the cross builds on emulated Cortex-M0+/M4 cores: golden vectors
#             bit-exact with the host build, and the cycle budgets
#   pytest    Python tests in tests/python/, when there are any
#   clone     a plain `git clone` of HEAD, alone in an empty folder, builds
#             and passes test_reference: nothing beside the repository needed
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

log() { printf '[test] %s\n' "$*"; }

# The checkout's state: HEAD, and a digest of the changes to tracked files
# and of the untracked files' names. The steps build from the checkout and
# .venv imports tools/python from it (editable: scripts/setup.sh), so a
# checkout changed while they run (a merge, a checkout of another branch)
# is tested half old, half new; the run then fails, saying so.
tree_state() {
  git rev-parse HEAD 2>/dev/null || return 0
  { git diff HEAD; git status --porcelain; } 2>/dev/null | git hash-object --stdin
}
state_before=$(tree_state)

./scripts/setup.sh

jobs=$(nproc 2>/dev/null || echo 2)
summary=()
failed=0
skip_reason=""

# run_step <name> <command...>: runs one step and records its outcome;
# exit status 77 means skipped, with the reason in skip_reason.
# Step functions chain with && because errexit is off inside a condition.
run_step() {
  local name=$1 rc=0
  shift
  log "=== $name ==="
  "$@" || rc=$?
  if ((rc == 0)); then
    summary+=("$name: ok")
  elif ((rc == 77)); then
    summary+=("$name: skipped ($skip_reason)")
  else
    summary+=("$name: FAILED (exit $rc)")
    failed=1
  fi
}

step_ctest() {
  ctest --test-dir build --output-on-failure --no-tests=error --parallel "$jobs"
}

step_asan() {
  cmake -S . -B build-asan --log-level=WARNING \
    -DCMAKE_BUILD_TYPE=Debug \
    -DPNEUFRAC_SANITIZE=ON \
    -DPNEUFRAC_BUILD_TESTS=ON &&
    cmake --build build-asan --parallel "$jobs" &&
    UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1} \
    ctest --test-dir build-asan --output-on-failure --no-tests=error --parallel "$jobs"
}

# Static analysis of the C sources that ship: library, tools and port. Any
# finding fails the step (--error-exitcode).
step_lint() {
  local dirs=(lib/src tools/host tools/cli)
  [[ -d port ]] && dirs+=(port)
  cppcheck --std=c99 --enable=warning,performance,portability --inline-suppr \
    --quiet --error-exitcode=1 -UPF_CONFIG_HEADER -Ilib/include -Ilib/src \
    "${dirs[@]}"
}

step_firmware() {
  ./scripts/firmware-check.sh
}

# One pytest-xdist worker per core, as step_pytest: each test runs its own
# emulator in its worker's process; the images are built once for both
# (tests/target/conftest.py), the cross builds under a lock (mcuemu.images).
step_target() {
  PNEUFRAC_BUILD_DIR="$PWD/build" .venv/bin/python -m pytest -q -n "$jobs" --durations=10 tests/target
}

step_pytest() {
  if [[ ! -d tests/python ]] ||
     [[ -z $(find tests/python -name 'test_*.py' -o -name '*_test.py' | head -n 1) ]]; then
    skip_reason="no tests in tests/python"
    return 77
  fi
  # Test files exist, so pytest's "no tests collected" (exit 5) is a failure too.
  # One pytest worker per core (pytest-xdist): the diagnoses are CPU-bound and
  # one process took 28 of a 35-min run. --dist loadfile keeps each file on
  # one worker, so that a module-scoped fixture (a record built and diagnosed
  # once for all of its file's tests) is not computed again on another one.
  # --durations: the log names the slowest tests, where the time goes.
  PNEUFRAC_BUILD_DIR="$PWD/build" \
  PNEUFRAC_LIBRARY="$PWD/build/lib/libpneufrac.so" \
    .venv/bin/python -m pytest -q -n "$jobs" --dist loadfile --durations=20 tests/python
}

# A user's clone has nothing beside it (no ../shared): the reference test
# must pass there on the repository's own files. Tests the committed HEAD.
step_clone() {
  local tmp rc=0
  if ! git rev-parse --git-dir >/dev/null 2>&1; then
    skip_reason="not a git checkout"
    return 77
  fi
  [[ -z $(git status --porcelain --untracked-files=no) ]] ||
    log "note: uncommitted changes are not in the clone; it tests HEAD"
  tmp=$(mktemp -d)
  {
    git clone -q "$PWD" "$tmp/pneufrac" &&
      cmake -S "$tmp/pneufrac" -B "$tmp/pneufrac/build" --log-level=WARNING \
        -DPNEUFRAC_BUILD_TESTS=ON >/dev/null &&
      cmake --build "$tmp/pneufrac/build" --parallel "$jobs" \
        --target test_reference >/dev/null &&
      ctest --test-dir "$tmp/pneufrac/build" -R '^test_reference$' \
        --output-on-failure --no-tests=error -V >"$tmp/ctest.log" 2>&1 &&
      grep -q 'skipped: no shared reference' "$tmp/ctest.log"
  } || rc=$?
  grep -E 'test_step_matches|skipped:|tests passed|FAILED' "$tmp/ctest.log" 2>/dev/null || true
  rm -rf "$tmp"
  return "$rc"
}

run_step ctest step_ctest
run_step asan step_asan
run_step lint step_lint
run_step firmware step_firmware
run_step target step_target
run_step pytest step_pytest
run_step clone step_clone

if [[ $(tree_state) != "$state_before" ]]; then
  summary+=("checkout: CHANGED while the steps ran: they tested two versions; run again on a still tree")
  failed=1
fi

log "=== summary ==="
for line in "${summary[@]}"; do
  log "$line"
done
exit "$failed"
