#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Cross-builds lib/ for Cortex-M0+ (Q15 runtime only) and Cortex-M4 (all of
# it), prints the code size of every object, and fails when the firmware
# library would drag in things a microcontroller build must not need:
#   - heap or stdio, on either core;
#   - any floating-point helper or libm call in the M0+ (no FPU) objects.
# The checks read undefined symbols (arm-none-eabi-nm -u), i.e. what each
# object asks the final link to supply.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

log() { printf '[firmware] %s\n' "$*"; }
# shellcheck source=scripts/fw-image.sh
. scripts/fw-image.sh

for tool in cmake arm-none-eabi-gcc arm-none-eabi-nm arm-none-eabi-size; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    log "missing $tool: run scripts/setup.sh first"
    exit 1
  fi
done

# Extended regexes, matched against whole symbol names.
# Allocation, including newlib's reentrant _malloc_r and friends.
heap_re='^_?(malloc|calloc|realloc|reallocarray|free|aligned_alloc|memalign|posix_memalign|valloc|strdup|strndup|sbrk)(_r)?$'
# Formatted and stream I/O. GCC may turn printf into puts/putchar and
# fprintf(stderr, ...) into fputc + _impure_ptr, so the stream objects count too.
stdio_re='^_?[a-z]*(printf|scanf)(_r)?$'
stdio_re+='|^_?(puts|fputs|putchar|putc|fputc|getchar|getc|fgetc|gets|fgets|fopen|fdopen|freopen|fclose|fread|fwrite|fflush|fseek|fseeko|ftell|ftello|rewind|fgetpos|fsetpos|perror|setbuf|setvbuf|ungetc|tmpfile|tmpnam|remove|rename|fileno|clearerr|feof|ferror)(_r)?$'
stdio_re+='|^(stdin|stdout|stderr|_impure_ptr|_global_impure_ptr|__sF)$'
# Soft-float helpers (EABI and generic libgcc names) and libm.
float_re='^__aeabi_[fd]|^__aeabi_[iul]+2[fd]$'
float_re+='|^__(add|sub|mul|div|neg|eq|ne|lt|le|gt|ge|un|cmp)[sdt]f[23]$|^__(float|fix|extend|trunc)'
float_re+='|^(__ieee754_)?(sqrt|cbrt|exp|exp2|expm1|log|log2|log10|log1p|pow|sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|floor|ceil|round|lround|llround|trunc|fmod|remainder|modf|frexp|ldexp|scalbn|hypot|fabs|fmin|fmax|fma|rint|lrint|llrint|nearbyint|erf|erfc|tgamma|lgamma|copysign)[fl]?$'

# Budgets of Example 6 in Q15, from a linked image: runtime code plus its
# coefficient set in flash, the instance in RAM. The full controller at the
# default order, and its reduced-order bank (issue 9's aim: 3 KB, 512 B).
flash_budget=6144
ram_budget=1024
bank_flash_budget=3072
bank_ram_budget=512

# Objects that must exist in the M0+ archive: the per-sample Q15 paths.
m0_required_objects=(pf_fracop_q15.c.obj pf_ctrl_q15.c.obj pf_bank_q15.c.obj)

violations=()

# Prints "<object> <symbol>" for every undefined symbol in an archive.
undefined_symbols() {
  # POSIX format: "archive[member]: symbol U"
  arm-none-eabi-nm -u -A -P "$1" | awk '{
    obj = $1; sub(/^.*\[/, "", obj); sub(/\]:$/, "", obj)
    print obj, $2
  }'
}

# check <archive> <what> <regex>: records each undefined symbol matching regex.
check() {
  local archive=$1 what=$2 re=$3 obj sym
  while read -r obj sym; do
    if [[ $sym =~ $re ]]; then
      violations+=("$archive: $obj references $sym ($what)")
    fi
  done < <(undefined_symbols "$archive")
}

# The example firmware (port/cortex-m) needs the host-exported coefficients.
gen_dir=build-arm-gen
host_cli=build/tools/pneufrac
if [[ ! -x $host_cli ]]; then
  log "building the host CLI to export coefficients"
  cmake -S . -B build --log-level=WARNING >/dev/null &&
    cmake --build build --target pneufrac_cli >/dev/null
fi
mkdir -p "$gen_dir"
"$host_cli" design --config dd --fs 20000 --arith q15 --in-fs 1 --out-fs 0.01 \
  --format c --name pf_example6_q15 >"$gen_dir/pf_example6_q15.h"
# ... and its reduced-order bank, from the Python tool (scripts/setup.sh)
.venv/bin/pneufrac-reduce --config dd --fs 20000 --in-fs 1 --out-fs 0.01 \
  --format c --name pf_example6_bank -o "$gen_dir/pf_example6_bank.h"

# link_example <cpu> <dir> <archive> <what> <flash budget> <RAM budget>
# [gcc args]: links port/cortex-m/example_isr.c (a Q15 Example 6 run from an
# ISR; -DPF_EXAMPLE_BANK: its bank) with startup.c into a real image and
# checks the budgets.
link_example() {
  local cpu=$1 dir=$2 archive=$3 what=$4 fb=$5 rb=$6 ctrl_flash inst_ram elf
  shift 6
  elf=$dir/example6-${what// /-}.elf
  fw_link "$cpu" "$archive" port/cortex-m/example_isr.c "$gen_dir" "$elf" \
    port/cortex-m/startup.c "$@" || return 1
  log "example image $elf ($cpu): whole image, then the controller's share"
  arm-none-eabi-size -B "$elf"
  read -r ctrl_flash inst_ram < <(fw_measure "$elf")
  if ((inst_ram == 0 || ctrl_flash == 0)); then
    violations+=("$cpu: could not measure the example's $what in $elf")
    return 0
  fi
  log "Q15 dd $what on $cpu: flash $ctrl_flash B (budget $fb), instance $inst_ram B RAM (budget $rb)"
  if ((ctrl_flash > fb || inst_ram > rb)); then
    violations+=("$cpu: Q15 dd $what over budget (flash $ctrl_flash B, RAM $inst_ram B)")
  fi
}

status=0
for target in cortex-m0plus:build-arm-m0 cortex-m4:build-arm-m4; do
  cpu=${target%%:*}
  dir=${target#*:}
  log "building lib/ for $cpu in $dir/"
  if ! fw_build "$cpu" "$dir" -Os; then
    log "FAIL: the $cpu build did not compile"
    status=1
    continue
  fi
  archive=$dir/lib/libpneufrac.a

  log "size of $archive ($cpu), Berkeley format:"
  arm-none-eabi-size -B -t "$archive"

  check "$archive" "heap" "$heap_re"
  check "$archive" "stdio" "$stdio_re"
  if ! link_example "$cpu" "$dir" "$archive" controller "$flash_budget" "$ram_budget"; then
    violations+=("$cpu: the example firmware did not link")
  fi
  if ! link_example "$cpu" "$dir" "$archive" "reduced bank" "$bank_flash_budget" \
    "$bank_ram_budget" -DPF_EXAMPLE_BANK; then
    violations+=("$cpu: the reduced-bank example firmware did not link")
  fi

  if [[ $cpu == cortex-m0plus ]]; then
    members=$(arm-none-eabi-ar t "$archive")
    for obj in "${m0_required_objects[@]}"; do
      grep -qx "$obj" <<<"$members" || violations+=("$archive: $obj is missing from the M0+ archive")
    done
    # Every object of the M0+ archive is Q15 runtime, so none may touch floats.
    check "$archive" "floating point on a core without FPU" "$float_re"
  fi
done

if ((${#violations[@]} > 0)); then
  log "FAIL: the firmware library breaks its rules (no heap, no stdio; no float on M0+):"
  printf '  %s\n' "${violations[@]}"
  status=1
fi

if ((status == 0)); then
  log "ok: no heap, no stdio, and no floating point in the M0+ objects"
fi
exit "$status"
