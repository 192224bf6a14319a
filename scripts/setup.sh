#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Prepares a Debian 12 machine for pneufrac and builds it into build/.
# Safe to run again: each step is skipped when its result is already there.
#   1. Debian packages (apt only when one is missing)
#   2. Python venv in .venv/ with the analysis and test packages, and
#      the pneufrac Python API with pneufrac-fit (tools/python) installed
#      editable
#   3. CMake configure + build (Release, tests on)
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

log() { printf '[setup] %s\n' "$*"; }

# g++: the exported headers are compiled as C++ too (test_export);
# liblapacke-dev: eigenvalues for `pneufrac design --format zpk|sos`;
# groff-base: the man pages' lint (docs/man/generate.py --check);
# systemd, man-db: `systemd-analyze verify` of the installed unit, which
# looks up its man:pneufracd(8) (ctest service_unit; no running systemd
# needed); iproute2: the recipe checks' private loopback (tests/recipes).
apt_packages=(
  cmake make gcc g++ libc6-dev pkg-config
  libcmocka-dev libmodbus-dev mbpoll liblapacke-dev groff-base
  systemd man-db iproute2
  libssl-dev openssl
  gcc-arm-none-eabi libnewlib-arm-none-eabi
  valgrind cppcheck
  python3 python3-venv
)
# Each of these imports under its own PyPI name.
python_packages=(numpy scipy matplotlib pymodbus pytest xdist mpmath cryptography control
                 pandas distributed pyarrow)
# pip requirements: the README's pymodbus example and the integration tests
# use the 3.x client API (device_id=, convert_to_registers), tested with 3.16.
# pytest-xdist (imports as xdist): scripts/test.sh runs tests/python on every
# core; one process ran them in 28 min of a 35-min CI run.
# mpmath: tests/ref/make_reference.py, and the test that checks its table.
# cryptography: the Modbus/TCP Security test makes its CA and certificates
# (tests/integration/test_tls.py).
# control (python-control) and pandas: tests/interface checks the exports
# with them, and the CSV files as pandas reads them; pandas is also the
# Python API's table type (to_frame).
# dask[distributed] and pyarrow: `pneufrac-fit fleet` runs the diagnoses on
# dask.distributed and writes its report as Parquet too.
# scipy: the range the package states (tools/python/pyproject.toml, with
# why), installed with the rest so that python-control cannot pull another.
# numpy is not pinned: nothing rests on its version (the cache's digests
# live within one run).
scipy_spec=$(sed -n 's/.*"\(scipy[<>=][^"]*\)".*/\1/p' tools/python/pyproject.toml)
scipy_minor=${scipy_spec#scipy>=}
scipy_minor=${scipy_minor%%,*}
pip_specs=(numpy "$scipy_spec" matplotlib "pymodbus>=3.16,<4" pytest pytest-xdist mpmath
           cryptography control pandas "dask[distributed]" pyarrow)

# --- 1. Debian packages ------------------------------------------------------
missing=()
for pkg in "${apt_packages[@]}"; do
  if [[ $(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null) != installed ]]; then
    missing+=("$pkg")
  fi
done

if ((${#missing[@]} > 0)); then
  log "installing Debian packages: ${missing[*]}"
  sudo=()
  if ((EUID != 0)); then
    sudo=(sudo)
  fi
  apt_log=$(mktemp)
  trap 'rm -f "$apt_log"' EXIT
  if ! { "${sudo[@]}" apt-get update -qq &&
         "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
           apt-get install -y -qq --no-install-recommends "${missing[@]}"; } >"$apt_log" 2>&1; then
    cat "$apt_log" >&2
    log "apt-get failed"
    exit 1
  fi
else
  log "Debian packages: all present"
fi

# --- 2. Python venv ----------------------------------------------------------
venv_python=.venv/bin/python
if ! "$venv_python" -c 'import sys' >/dev/null 2>&1; then
  # Missing, or left broken by a Python that is gone: start over.
  log "creating Python venv in .venv/"
  rm -rf .venv
  python3 -m venv .venv
fi

import_check="import $(IFS=,; echo "${python_packages[*]}"); v = tuple(int(x) for x in pymodbus.__version__.split('.')[:2]); assert (3, 16) <= v < (4, 0); assert '.'.join(scipy.__version__.split('.')[:2]) == '$scipy_minor'"
if "$venv_python" -c "$import_check" >/dev/null 2>&1; then
  log "Python packages: all present"
else
  log "installing Python packages: ${python_packages[*]}"
  "$venv_python" -m pip install --quiet "${pip_specs[@]}"
fi

# The Python side (tools/python), editable: the pneufrac API with its
# ctypes binding, which finds build/lib/libpneufrac.so from the checkout;
# pneufrac-fit; pneufrac-reduce; and pneufrac-plot, which `pneufrac
# bode|step --plot` runs. The distribution was called pneufrac-fit before
# it held the API: a venv that still has that one gets it replaced.
py_check="import pneufrac, pneufrac_fit, pneufrac_reduce, pathlib, sys; sys.exit(any(pathlib.Path(m.__file__).resolve().parent != pathlib.Path('tools/python', m.__name__).resolve() for m in (pneufrac, pneufrac_fit, pneufrac_reduce)))"
if [[ -x .venv/bin/pneufrac-fit && -x .venv/bin/pneufrac-plot && -x .venv/bin/pneufrac-reduce ]] &&
   "$venv_python" -c "$py_check" >/dev/null 2>&1; then
  log "pneufrac (Python API, pneufrac-fit, pneufrac-reduce): installed"
else
  log "installing pneufrac (Python API, pneufrac-fit, pneufrac-reduce; tools/python, editable)"
  if "$venv_python" -m pip show --quiet pneufrac-fit >/dev/null 2>&1; then
    "$venv_python" -m pip uninstall --quiet --yes pneufrac-fit
  fi
  "$venv_python" -m pip install --quiet --disable-pip-version-check -e tools/python
fi

# The firmware emulator (tools/mcuemu, editable): on-target tests and the
# cycle table; it brings unicorn, capstone and pyelftools.
emu_check="import mcuemu, unicorn, capstone, elftools, pathlib, sys; sys.exit(pathlib.Path(mcuemu.__file__).resolve().parent != pathlib.Path('tools/mcuemu/mcuemu').resolve())"
if "$venv_python" -c "$emu_check" >/dev/null 2>&1; then
  log "mcuemu: installed"
else
  log "installing mcuemu (tools/mcuemu, editable)"
  "$venv_python" -m pip install --quiet --disable-pip-version-check -e tools/mcuemu
fi

# --- 3. Build ----------------------------------------------------------------
log "configuring build/ (Release, tests on)"
cmake -S . -B build --log-level=WARNING \
  -DCMAKE_BUILD_TYPE=Release \
  -DPNEUFRAC_BUILD_TESTS=ON
log "building"
cmake --build build --parallel "$(nproc 2>/dev/null || echo 2)"
log "done: library in build/lib/, run scripts/test.sh for the tests"
