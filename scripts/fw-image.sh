# SPDX-License-Identifier: MIT
# Sourced by scripts/firmware-check.sh and bench/run.sh (and run by the
# emulator package tools/mcuemu as `bash scripts/fw-image.sh FUNCTION ARGS`),
# so that the budget check, the benchmarks and the on-target tests build,
# link and measure firmware images the same way.

# fw_build <cpu> <dir> <opt> [cmake args...]: cross-builds lib/ for <cpu>
# (cortex-m0plus or cortex-m4) at <opt> (-Os, the firmware default, or -O2)
# into <dir>; extra arguments (-DPNEUFRAC_BANK_ASM=OFF) go to cmake.
# Chained with && because errexit is off inside an "if" condition.
fw_build() {
  local cpu=$1 dir=$2 opt=$3
  shift 3
  cmake -S . -B "$dir" --log-level=WARNING \
    -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/arm-none-eabi.cmake" \
    -DCMAKE_BUILD_TYPE=MinSizeRel \
    -DPNEUFRAC_CPU="$cpu" -DPNEUFRAC_FW_OPT="$opt" "$@" &&
    cmake --build "$dir" --parallel "$(nproc 2>/dev/null || echo 2)"
}

# fw_link <cpu> <archive> <source> <incdir> <elf> [gcc args...]: links a
# Cortex-M image the way a firmware build would: -Os, newlib-nano,
# --gc-sections, the memory map of port/cortex-m/example.ld. Extra
# arguments (more sources, -Wl,-u,SYMBOL) go to gcc as they are.
fw_link() {
  local cpu=$1 archive=$2 src=$3 inc=$4 elf=$5 flags
  shift 5
  flags=(-mcpu="$cpu" -mthumb)
  [[ $cpu == cortex-m4 ]] && flags+=(-mfloat-abi=hard -mfpu=fpv4-sp-d16)
  arm-none-eabi-gcc "${flags[@]}" -std=c99 -Os -ffunction-sections -fdata-sections \
    -Wall -Wextra -Werror -Ilib/include -I"$inc" "$src" "$@" "$archive" -nostartfiles \
    --specs=nano.specs -T port/cortex-m/example.ld -Wl,--gc-sections -o "$elf"
}

# fw_measure <elf>: prints "<flash> <ram>": the bytes of every pf_* symbol
# (runtime code and coefficient set) plus the compiler helpers the runtime
# pulls in (__aeabi_*: 64-bit multiply and shifts on an M0+), and of the
# instance, 'controller'.
fw_measure() {
  local flash=0 ram=0 size type name
  while read -r _ size type name; do
    if [[ $type == [tTrR] && ($name == pf_* || $name == __aeabi_*) ]]; then
      flash=$((flash + 16#$size))
    elif [[ $name == controller ]]; then
      ram=$((16#$size))
    fi
  done < <(arm-none-eabi-nm -S "$1")
  echo "$flash $ram"
}

# Run directly: `bash scripts/fw-image.sh fw_build ARGS...` (from the
# repository root).
if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
  set -euo pipefail
  case ${1:-} in
    fw_build | fw_link | fw_measure) "$@" ;;
    *) echo "usage: $0 {fw_build|fw_link|fw_measure} ARGS..." >&2; exit 2 ;;
  esac
fi
