#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Consumer test: pneufrac used the ways docs/firmware.md says, each one
# building and running a tiny program, from scratch in a temporary folder:
#   0. cmake --install of this build: programs, man pages, docs, unit file
#   1. cmake --install of a library-only build; what the prefix holds
#   2. find_package(pneufrac) + pneufrac::pneufrac, also after moving the prefix
#   3. pkg-config, from the moved prefix
#   4. add_subdirectory: only the library is built, nothing of pneufrac installed
#   5. FetchContent from a source archive (a local file: no network)
#   6. no libmodbus: the daemon is skipped with a message, the rest builds
#   7. the firmware copy: the command block of docs/firmware.md, run as
#      written; the copied files alone link, none of them is superfluous,
#      and the result equals `pneufrac simulate --arith q15` sample for sample
#   usage: run.sh SOURCE_DIR PNEUFRAC_CLI [BUILD_DIR]
set -euo pipefail

SRC=$(cd "$1" && pwd)
CLI=$2
BUILD=${3:-}
HERE="$SRC/tests/consumer"
W=$(mktemp -d "${TMPDIR:-/tmp}/pneufrac-consumer.XXXXXX")
trap 'rm -rf "$W"' EXIT
jobs=$(nproc 2>/dev/null || echo 2)
log() { printf '[consumer] %s\n' "$*"; }
fail() { printf '[consumer] FAIL: %s\n' "$*" >&2; exit 1; }
quiet() { "$@" >"$W/log" 2>&1 || { cat "$W/log" >&2; fail "$*"; }; }

# consumer BUILD_DIR CMAKE_ARGS...: configure, build and run the consumer.
consumer() {
  local b=$1
  shift
  quiet cmake -S "$HERE" -B "$b" "$@"
  quiet cmake --build "$b" --parallel "$jobs"
  "$b/consumer" || fail "consumer in $b"
}

lib_only=(-DPNEUFRAC_BUILD_TOOLS=OFF -DPNEUFRAC_BUILD_PORT=OFF
          -DPNEUFRAC_BUILD_TESTS=OFF -DPNEUFRAC_BUILD_BENCH=OFF)

if [[ -n $BUILD ]]; then
  log "0. install this build"
  quiet cmake --install "$BUILD" --prefix "$W/full"
  for f in bin/pneufrac bin/pneufracd share/man/man1/pneufrac.1 share/man/man1/pneufrac-fit.1 \
           share/man/man8/pneufracd.8 share/doc/pneufrac/README.md share/doc/pneufrac/LICENSE \
           share/doc/pneufrac/control.md share/doc/pneufrac/pneufracd.md \
           lib/systemd/system/pneufracd.service; do
    [[ -e "$W/full/$f" ]] || fail "the installed prefix lacks $f"
  done
  "$W/full/bin/pneufrac" --version >/dev/null || fail "installed pneufrac does not run"
  # The unit names this prefix's daemon, not the default prefix's.
  grep -qx "ExecStart=$W/full/bin/pneufracd --config .*" \
       "$W/full/lib/systemd/system/pneufracd.service" \
    || fail "the installed unit does not run $W/full/bin/pneufracd"
fi

log "1. install a library-only build"
quiet cmake -S "$SRC" -B "$W/lib" "${lib_only[@]}"
quiet cmake --build "$W/lib" --parallel "$jobs"
quiet cmake --install "$W/lib" --prefix "$W/prefix"
for f in include/pneufrac/pneufrac.h lib/libpneufrac.a lib/cmake/pneufrac/pneufracConfig.cmake \
         lib/cmake/pneufrac/pneufracConfigVersion.cmake lib/pkgconfig/pneufrac.pc \
         share/doc/pneufrac/README.md share/doc/pneufrac/firmware.md; do
  [[ -e "$W/prefix/$f" ]] || fail "installed prefix lacks $f"
done
[[ ! -e "$W/prefix/bin" ]] || fail "a library-only install has bin/: $(ls "$W/prefix/bin")"

log "2. find_package, then again with the prefix moved"
consumer "$W/fp" -DCONSUME=find_package "-DCMAKE_PREFIX_PATH=$W/prefix"
mv "$W/prefix" "$W/moved"
consumer "$W/fp2" -DCONSUME=find_package "-DCMAKE_PREFIX_PATH=$W/moved"

log "3. pkg-config (from the moved prefix)"
export PKG_CONFIG_PATH="$W/moved/lib/pkgconfig"
[[ $(pkg-config --modversion pneufrac) == $("$CLI" --version | cut -d' ' -f2) ]] ||
  fail "pkg-config --modversion differs from pneufrac --version"
# shellcheck disable=SC2046  # the flags are words
cc -std=c99 -o "$W/pc" "$HERE/main.c" $(pkg-config --cflags --libs pneufrac) \
  "-Wl,-rpath,$W/moved/lib" || fail "cc with pkg-config flags"
"$W/pc" || fail "pkg-config program"
unset PKG_CONFIG_PATH

log "4. add_subdirectory"
consumer "$W/sub" -DCONSUME=subdirectory "-DPNEUFRAC_SOURCE=$SRC"
quiet cmake --install "$W/sub" --prefix "$W/sub-prefix"
installed=$(cd "$W/sub-prefix" && find . -type f | sort)
[[ $installed == "./bin/consumer" ]] || fail "installing the consumer also installed: $installed"

log "5. FetchContent from a source archive"
tar -C "$SRC" -czf "$W/pneufrac-src.tar.gz" --exclude='./build*' --exclude=./.venv \
  --exclude=./.git .
consumer "$W/fc" -DCONSUME=fetchcontent "-DPNEUFRAC_URL=file://$W/pneufrac-src.tar.gz"

log "6. no libmodbus: pneufracd skipped with a message"
mkdir -p "$W/no-pc"
PKG_CONFIG_LIBDIR="$W/no-pc" PKG_CONFIG_PATH="" cmake -S "$SRC" -B "$W/nomodbus" \
  -DPNEUFRAC_BUILD_TOOLS=OFF -DPNEUFRAC_BUILD_TESTS=OFF -DPNEUFRAC_BUILD_BENCH=OFF \
  -DPNEUFRAC_BUILD_PORT=ON >"$W/log" 2>&1 || { cat "$W/log" >&2; fail "configure without libmodbus"; }
grep -q "libmodbus (Debian: libmodbus-dev) not found; pneufracd is" "$W/log" || fail "no message about the skipped daemon"
quiet cmake --build "$W/nomodbus" --parallel "$jobs"

log "7. the firmware copy of docs/firmware.md"
block=$(sed -n '/<!-- firmware-copy -->/,/<!-- end firmware-copy -->/p' "$SRC/docs/firmware.md" |
        sed '1,/^```sh$/d; /^```$/,$d')
[[ -n $block ]] || fail "docs/firmware.md has no firmware-copy block"
FW="$W/fw"
(cd "$SRC" && FW=$FW bash -euo pipefail -c "$block") || fail "the copy commands"
"$CLI" design --config dd --fs 20000 --arith q15 --in-fs 1 --out-fs 0.01 --format c \
  --name pf_example6_q15 >"$FW/pf_example6_q15.h"
mapfile -t sources < <(cd "$FW/pneufrac" && ls ./*.c)
((${#sources[@]} > 0)) || fail "nothing copied"
flags=(-std=c99 -Wall -Wextra -pedantic -Werror -O2 -I"$FW/pneufrac" -I"$FW")
# shellcheck disable=SC2068
cc "${flags[@]}" -o "$W/fw.out" "$HERE/main_fw.c" ${sources[@]/#/$FW/pneufrac/} ||
  fail "the copied files do not build"
for drop in "${sources[@]}"; do
  rest=()
  for s in "${sources[@]}"; do [[ $s == "$drop" ]] || rest+=("$FW/pneufrac/$s"); done
  if cc "${flags[@]}" -o "$W/fw-less.out" "$HERE/main_fw.c" "${rest[@]}" 2>/dev/null; then
    fail "$drop is copied but not needed"
  fi
done
n=4000
"$W/fw.out" $n >"$W/fw.txt"
awk -v n=$n 'BEGIN { print "t,e"; for (k = 0; k < n; k++) printf "%.17g,0.5\n", k / 20000 }' >"$W/half.csv"
"$CLI" simulate --config dd --fs 20000 --duration "$(awk -v n=$n 'BEGIN { printf "%.17g", (n - 1) / 20000 }')" \
  --arith q15 --in-fs 1 --out-fs 0.01 --input "$W/half.csv" |
  grep -v '^#' | awk -F, 'NR > 1 { print $4 }' >"$W/sim.txt"
cmp -s "$W/fw.txt" "$W/sim.txt" || fail "firmware copy differs from pneufrac simulate"
if command -v arm-none-eabi-gcc >/dev/null; then
  for s in "${sources[@]}"; do
    arm-none-eabi-gcc -mcpu=cortex-m0plus -mthumb -Os -std=c99 -Wall -Wextra -pedantic \
      -Werror -I"$FW/pneufrac" -c "$FW/pneufrac/$s" -o "$W/m0.o" || fail "$s for Cortex-M0+"
  done
fi
log "all ways work: ${#sources[@]} source files for the firmware copy"
