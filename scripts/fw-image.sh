# SPDX-License-Identifier: MIT
# Sourced by scripts/firmware-check.sh and bench/run.sh, so that the budget
# check and the benchmark link and measure firmware images the same way.

# fw_link <cpu> <archive> <source> <incdir> <elf>: links a Cortex-M image
# the way a firmware build would: -Os, newlib-nano, --gc-sections, the
# memory map of port/cortex-m/example.ld.
fw_link() {
  local cpu=$1 archive=$2 src=$3 inc=$4 elf=$5 flags
  flags=(-mcpu="$cpu" -mthumb)
  [[ $cpu == cortex-m4 ]] && flags+=(-mfloat-abi=hard -mfpu=fpv4-sp-d16)
  arm-none-eabi-gcc "${flags[@]}" -std=c99 -Os -ffunction-sections -fdata-sections \
    -Wall -Wextra -Werror -Ilib/include -I"$inc" "$src" "$archive" -nostartfiles \
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
