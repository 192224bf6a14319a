#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Black-box tests of the pneufrac command-line tool.
#   usage: test_cli.sh PATH/TO/pneufrac
# Prints one line per check and "N passed, M failed"; exits 1 if any failed.
set -u

if [ $# -ne 1 ] || [ ! -x "$1" ]; then
  echo "usage: $0 PATH/TO/pneufrac" >&2
  exit 2
fi
BIN=$1
TMP=$(mktemp -d "${TMPDIR:-/tmp}/pneufrac-cli.XXXXXX") || exit 2
trap 'rm -rf "$TMP"' EXIT

passed=0
failed=0
ok() { echo "ok   - $1"; passed=$((passed + 1)); }
bad() { echo "FAIL - $1${2:+ ($2)}"; failed=$((failed + 1)); }

# check DESC COMMAND...: passes if the command succeeds.
check() {
  local desc=$1
  shift
  if "$@"; then ok "$desc"; else bad "$desc"; fi
}

# expect_err DESC REGEX ARGS...: the tool must exit 2, write nothing to
# stdout and exactly one line "pneufrac: ..." matching REGEX to stderr.
expect_err() {
  local desc=$1 re=$2 rc lines msg
  shift 2
  "$BIN" "$@" >"$TMP/out" 2>"$TMP/err"
  rc=$?
  lines=$(wc -l <"$TMP/err")
  msg=$(head -c 300 "$TMP/err" | tr '\n' '|')
  if [ "$rc" -ne 2 ]; then
    bad "$desc" "exit $rc, want 2: $msg"
  elif [ "$lines" -ne 1 ]; then
    bad "$desc" "$lines stderr lines: $msg"
  elif ! grep -q '^pneufrac: ' "$TMP/err"; then
    bad "$desc" "no 'pneufrac: ' prefix: $msg"
  elif ! grep -qE -- "$re" "$TMP/err"; then
    bad "$desc" "message does not match /$re/: $msg"
  elif [ -s "$TMP/out" ]; then
    bad "$desc" "wrote to stdout"
  else
    ok "$desc"
  fi
}

# run_ok FILE ARGS...: runs the tool with stdout to FILE; passes on exit 0
# with an empty stderr.
run_ok() {
  local out=$1
  shift
  "$BIN" "$@" >"$out" 2>"$TMP/err" && [ ! -s "$TMP/err" ]
}

# csv_awk [AWK OPTIONS] PROGRAM FILE: awk -F, over FILE without its '#'
# lines (the units line), so NR counts the header and the data rows.
csv_awk() {
  local file=${*: -1}
  grep -v '^#' "$file" | awk -F, "${@:1:$#-1}"
}

SIM=(simulate --config dd --fs 1000 --duration 0.05)

# --- help and version -------------------------------------------------------
check "--help exits 0 with usage on stdout" \
  bash -c '"$1" --help >"$2/o" 2>"$2/e" && grep -q "^usage: pneufrac" "$2/o" && [ ! -s "$2/e" ]' _ "$BIN" "$TMP"
check "simulate --help exits 0 with usage on stdout" \
  bash -c '"$1" simulate --help >"$2/o" 2>"$2/e" && grep -q "^usage: pneufrac simulate" "$2/o" && [ ! -s "$2/e" ]' _ "$BIN" "$TMP"
# Exit status 3 belongs to --plot: listed by the commands that have it only.
for c in step bode; do
  check "$c --help lists exit status 3 (--plot)" \
    bash -c '"$1" "$2" --help | grep -q "^3 --plot"' _ "$BIN" "$c"
done
for c in simulate design demo reproduce; do
  check "$c --help lists no exit status 3 (no --plot)" \
    bash -c '"$1" "$2" --help >"$3/o" && grep -q "^Exit status:" "$3/o" && ! grep -q "3 --plot" "$3/o"' \
    _ "$BIN" "$c" "$TMP"
done
check "--version prints the version" \
  bash -c '"$1" --version | grep -qE "^pneufrac [0-9]+\.[0-9]+\.[0-9]+$"' _ "$BIN"

# --- shape of the output ----------------------------------------------------
if run_ok "$TMP/step.csv" "${SIM[@]}"; then
  ok "default step run exits 0"
else
  bad "default step run exits 0"
fi
check "header is t,e,pc" test "$(head -n 1 "$TMP/step.csv")" = "t,e,pc"
check "the units follow as a comment" \
  test "$(sed -n 2p "$TMP/step.csv")" = "# units: s,input units,output units"
check "numbers are the shortest that read back (t = 0.001, not 0.0010000000000000000)" \
  grep -q "^0.001,1," "$TMP/step.csv"
check "row count is round(0.05*1000)+1 = 51" \
  test "$(($(grep -vc "^#" "$TMP/step.csv") - 1))" -eq 51
check "first row has t=0, e=1" \
  bash -c 'grep -v "^#" "$1" | sed -n 2p | grep -qE "^0,1,[^,]+$"' _ "$TMP/step.csv"
check "t = n/fs and e = 1 on every row" \
  csv_awk 'NR > 1 { n = NR - 2; if ($1 != n / 1000 || $2 != 1 || NF != 3) bad = 1 }
           END { exit bad }' "$TMP/step.csv"
check "the step response rises" \
  csv_awk 'NR == 2 { a = $3 } NR > 2 { b = $3 } END { exit !(b > a && a > 0) }' "$TMP/step.csv"

for spec in "3 0.5 3" "1000 0.0004 1" "20000 0.00005 2"; do
  read -r fs dur want <<<"$spec"
  if run_ok "$TMP/r.csv" simulate --config p --fs "$fs" --duration "$dur"; then
    check "fs=$fs duration=$dur gives $want rows" \
      test "$(($(grep -vc "^#" "$TMP/r.csv") - 1))" -eq "$want"
  else
    bad "fs=$fs duration=$dur runs"
  fi
done

for cfg in p id pid; do
  check "config $cfg runs" run_ok "$TMP/c.csv" simulate --config "$cfg" --fs 2000 --duration 0.1
done
check "design options are accepted" run_ok "$TMP/o.csv" "${SIM[@]}" --band 0.01:3000 \
  --order 4 --approx refined --input-model linear --t-slow 5 --set beta=0.7 --set=q=0.8
check "--set changes the response" \
  bash -c '! cmp -s "$1" "$2"' _ "$TMP/step.csv" "$TMP/o.csv"

# --- q15 --------------------------------------------------------------------
if run_ok "$TMP/q.csv" simulate --config id --fs 1000 --duration 0.2 --arith q15 \
  --in-fs 2 --out-fs 16; then
  ok "q15 run exits 0"
else
  bad "q15 run exits 0" "$(head -c 300 "$TMP/err")"
fi
check "q15 header is t,e,pc,pc_q15" test "$(head -n 1 "$TMP/q.csv")" = "t,e,pc,pc_q15"
check "q15 has round(0.2*1000)+1 rows" test "$(($(grep -vc "^#" "$TMP/q.csv") - 1))" -eq 201
check "q15: pc = pc_q15*out_fs/32768 and pc_q15 is an int16" \
  csv_awk -v ofs=16 'NR > 1 { if (NF != 4 || $4 !~ /^-?[0-9]+$/ || $4 < -32768 ||
                               $4 > 32767 || $3 != $4 * ofs / 32768) bad = 1 }
                     END { exit bad || NR != 202 }' "$TMP/q.csv"
run_ok "$TMP/qd.csv" simulate --config id --fs 1000 --duration 0.2
check "q15 stays within 0.5 % of full scale of double" \
  bash -c 'paste -d, <(grep -v "^#" "$1") <(grep -v "^#" "$2") | awk -F, "NR > 1 { d = \$3 - \$7; if (d < 0) d = -d; if (d > 0.005 * 16) bad = 1 } END { exit bad }"' \
  _ "$TMP/q.csv" "$TMP/qd.csv"
check "q15 saturates a huge input instead of wrapping" \
  bash -c 'printf "t,e\n0,1e6\n0.001,-1e6\n" >"$2/huge.csv" &&
           "$1" simulate --config p --fs 1000 --duration 0.01 --arith q15 --in-fs 1 --out-fs 1 \
             --input "$2/huge.csv" >"$2/h.csv" 2>"$2/e" && [ ! -s "$2/e" ] &&
           [ "$(($(grep -vc "^#" "$2/h.csv") - 1))" -eq 11 ]' _ "$BIN" "$TMP"
check "q15 supports saturation, lag and dead time" run_ok "$TMP/qe.csv" \
  simulate --config dd --fs 1000 --duration 0.05 --arith q15 --in-fs 1 --out-fs 0.02 \
  --effect saturation:lo=-0.01,hi=0.01 --effect lag:tau=0.002 --effect deadtime:t=0.003

# --- float against double ---------------------------------------------------
for cfg in p dd id pid; do
  run_ok "$TMP/fd.csv" simulate --config "$cfg" --fs 1000 --duration 2
  run_ok "$TMP/ff.csv" simulate --config "$cfg" --fs 1000 --duration 2 --arith float
  check "float agrees with double to 1e-5 relative ($cfg, 2001 samples)" \
    bash -c 'paste -d, <(grep -v "^#" "$1") <(grep -v "^#" "$2") | awk -F, "NR > 1 { d = \$3; f = \$6; a = d < 0 ? -d : d; r = f - d; if (r < 0) r = -r;
             if (r > 1e-5 * a) bad = 1; n++ } END { exit bad || n != 2001 }"' _ "$TMP/fd.csv" "$TMP/ff.csv"
done

# --- --input ----------------------------------------------------------------
# The tool's own output is a valid input (columns t, e and one more).
check "--input of a unit step reproduces the default run bit for bit" \
  bash -c '"$1" simulate --config dd --fs 1000 --duration 0.05 --input "$2/step.csv" | cmp -s - "$2/step.csv"' \
  _ "$BIN" "$TMP"
{
  printf '# unit step, short, with comments and extra columns\n\n'
  printf 'x, e ,t\n'
  printf '7,1,0\n# a comment between rows\n\n9,1,0.001\n5,1,0.002\r\n'
} >"$TMP/short.csv"
check "a short input file holds its last value (comments, blanks, CRLF ok)" \
  bash -c '"$1" simulate --config dd --fs 1000 --duration 0.05 --input "$2/short.csv" | cmp -s - "$2/step.csv"' \
  _ "$BIN" "$TMP"
check "--input - reads standard input" \
  bash -c '"$1" simulate --config dd --fs 1000 --duration 0.05 --input - <"$2/short.csv" | cmp -s - "$2/step.csv"' \
  _ "$BIN" "$TMP"
printf 't,e\n0,0\n0.001,0\n0.002,1\n' >"$TMP/late.csv"
check "input follows the file: zero input gives zero output" \
  bash -c '"$1" simulate --config dd --fs 1000 --duration 0.01 --input "$2/late.csv" | grep -v "^#" |
           awk -F, "NR == 2 || NR == 3 { if (\$2 != 0 || \$3 != 0) bad = 1 } NR == 4 { if (\$2 != 1 || \$3 <= 0) bad = 1 } END { exit bad }"' \
  _ "$BIN" "$TMP"

# bad_csv NAME REGEX CONTENT: the file must be refused with its name:line.
bad_csv() {
  local name=$1 re=$2
  printf "$3" >"$TMP/$name.csv"
  expect_err "bad input: $name" "$TMP/$name.csv:$re" "${SIM[@]}" --input "$TMP/$name.csv"
}
bad_csv nonuniform '4: .*1/fs' 't,e\n0,1\n0.001,1\n0.0025,1\n'
bad_csv backwards '4: t is not increasing' 't,e\n0,1\n0.001,1\n0.0005,1\n'
bad_csv nan '3: .*not a finite number' 't,e\n0,1\n0.001,nan\n'
bad_csv inf '2: .*not a finite number' 't,e\n0,inf\n'
bad_csv garbage '4: .*abc' 't,e\n0,1\n0.001,1\n0.002,abc\n'
bad_csv trailing '2: .*1x' 't,e\n0,1x\n'
bad_csv no_e_column "1: header has no column 'e'" 't,u\n0,1\n'
bad_csv no_t_column "2: header has no column 't'" '# c\ne,u\n0,1\n'
bad_csv short_row '3: 1 fields, the header has 2' 't,e\n0,1\n0.001\n'
# a spreadsheet's ';' or tab separator is named (was "header has no column 'e'")
bad_csv semicolons "1: the header's fields are separated by ';'" 't;e\n0;1\n0,001;1\n'
bad_csv tabs "1: the header's fields are separated by '.t'" 't\te\n0\t1\n'
bad_csv empty_field "2: empty field 'e'" 't,e\n0,\n'
printf '' >"$TMP/empty.csv"
bad_csv header_only '1: no data rows' 't,e\n'
expect_err "bad input: empty" "$TMP/empty.csv: empty file" "${SIM[@]}" --input "$TMP/empty.csv"
bad_csv dup_column "1: column 'e' appears twice" 't,e,e\n0,1,1\n'
expect_err "missing input file" "nonexistent.csv: cannot open" "${SIM[@]}" --input "$TMP/nonexistent.csv"
expect_err "input that is a directory" "$TMP:1: read error" "${SIM[@]}" --input "$TMP"

# --- effects ----------------------------------------------------------------
for fx in backlash:width=0.01 nozzle:xh=0.5 saturation:lo=-0.005,hi=0.005 deadtime:t=0.01 lag:tau=0.005; do
  check "--effect $fx runs" run_ok "$TMP/fx.csv" "${SIM[@]}" --effect "$fx"
done
run_ok "$TMP/dt.csv" "${SIM[@]}" --effect deadtime:t=0.01
check "dead time of 10 samples delays the output" \
  csv_awk 'NR > 1 && NR <= 11 { if ($3 != 0) bad = 1 } NR == 12 { if ($3 <= 0) bad = 1 } END { exit bad }' "$TMP/dt.csv"
run_ok "$TMP/sat.csv" "${SIM[@]}" --effect saturation:lo=-0.002,hi=0.002
check "saturation bounds p_c" \
  csv_awk 'NR > 1 { if ($3 > 0.002 || $3 < -0.002) bad = 1 } END { exit bad }' "$TMP/sat.csv"
run_ok "$TMP/stop.csv" "${SIM[@]}" --effect saturation:lo=-0.002,hi=0.002,kind=2
check "the relay's stop bounds p_c" \
  csv_awk 'NR > 1 { if ($3 > 0.002 || $3 < -0.002) bad = 1 } END { exit bad }' "$TMP/stop.csv"
expect_err "effect: saturation kind out of the table's range" "saturate.*from 1 to 3" \
  "${SIM[@]}" --effect saturation:lo=-1,hi=1,kind=4
# the wound-on relay's state outgrows any fixed Q15 scale: refused, and said so
expect_err "effect: wound-on saturation refused in q15" "memory winds on" \
  "${SIM[@]}" --arith q15 --in-fs 1 --out-fs 1 --effect saturation:lo=-0.5,hi=0.5,kind=3
expect_err "effect: saturation kind not whole" "not a placement, a whole number" \
  "${SIM[@]}" --effect saturation:lo=-1,hi=1,kind=1.5
# kind 0 is the library's "off": asked for a saturation, it must not vanish
expect_err "effect: saturation kind 0 would switch it off" "not a placement" \
  "${SIM[@]}" --effect saturation:lo=-1,hi=1,kind=0

expect_err "effect: unknown name" "unknown effect 'spring'.*backlash.*lag" "${SIM[@]}" --effect spring:k=1
expect_err "effect: unknown key" "unknown key 'w'.*valid: width" "${SIM[@]}" --effect backlash:w=1
expect_err "effect: no keys" "expected lag:KEY=VALUE" "${SIM[@]}" --effect lag
expect_err "effect: key without value" "needs a value" "${SIM[@]}" --effect lag:tau
expect_err "effect: non-numeric value" "not a finite number" "${SIM[@]}" --effect lag:tau=1s
expect_err "effect: NaN value" "not a finite number" "${SIM[@]}" --effect deadtime:t=nan
expect_err "effect: missing key" "missing key 'hi'" "${SIM[@]}" --effect saturation:lo=0
expect_err "effect: repeated key" "'lo' given twice" "${SIM[@]}" --effect saturation:lo=0,lo=1
expect_err "effect: given twice" "lag given twice" "${SIM[@]}" --effect lag:tau=1 --effect lag:tau=2
expect_err "effect: negative value is invalid" "invalid parameter 'lag'" "${SIM[@]}" --effect lag:tau=-1
expect_err "effect: saturation lo >= hi" "invalid parameter 'sat_hi'" "${SIM[@]}" --effect saturation:lo=1,hi=0
check "--effect nozzle and backlash run in q15" run_ok "$TMP/nzq.csv" "${SIM[@]}" --arith q15 \
  --in-fs 1 --out-fs 1 --effect nozzle:xh=0.1 --effect backlash:width=0.01
expect_err "refined approximation not in q15" "q15 does not support the refined" "${SIM[@]}" \
  --arith q15 --in-fs 1 --out-fs 1 --approx refined

# --- bad arguments ----------------------------------------------------------
expect_err "no command" "no command" 
expect_err "unknown command" "unknown command 'simulat'" simulat
expect_err "unknown option" "unknown option '--bogus'" "${SIM[@]}" --bogus 1
expect_err "positional argument" "unexpected argument 'extra'" "${SIM[@]}" extra
expect_err "missing value at the end" "--duration needs a value" simulate --config dd --fs 1000 --duration
expect_err "missing value before an option" "--fs needs a value" simulate --config dd --fs --duration 1
expect_err "missing --config" "missing --config" simulate --fs 1000 --duration 1
expect_err "missing --fs" "missing --fs" simulate --config dd --duration 1
expect_err "missing --duration" "missing --duration" simulate --config dd --fs 1000
expect_err "unknown config" "unknown configuration 'pd'" simulate --config pd --fs 1000 --duration 1
expect_err "non-numeric fs" "'fast' is not a finite number" simulate --config dd --fs fast --duration 1
expect_err "trailing garbage 20k" "'20k' is not a finite number" simulate --config dd --fs 20k --duration 1
expect_err "NaN fs" "'nan' is not a finite number" simulate --config dd --fs nan --duration 1
expect_err "inf duration" "'inf' is not a finite number" simulate --config dd --fs 1000 --duration inf
expect_err "overflowing duration" "not a finite number" simulate --config dd --fs 1000 --duration 1e999
expect_err "empty fs" "not a finite number" simulate --config dd --fs= --duration 1
expect_err "leading blank" "not a finite number" simulate --config dd --fs " 1000" --duration 1
expect_err "negative fs" "--fs must be > 0" simulate --config dd --fs -1000 --duration 1
expect_err "zero fs" "--fs must be > 0" simulate --config dd --fs 0 --duration 1
expect_err "negative duration" "--duration must be > 0" simulate --config dd --fs 1000 --duration -1
expect_err "zero duration" "--duration must be > 0" simulate --config dd --fs 1000 --duration 0
expect_err "more than 1e9 samples" "at most 1000000000" simulate --config dd --fs 1e6 --duration 1001
expect_err "fs above the library's limit" "invalid parameter 'fs'" simulate --config dd --fs 2e7 --duration 1e-3
expect_err "option given twice" "--fs given more than once" "${SIM[@]}" --fs 2000
expect_err "unknown arith" "unknown arithmetic 'fixed'" "${SIM[@]}" --arith fixed
expect_err "--in-fs without q15" "only with --arith q15" "${SIM[@]}" --in-fs 1
expect_err "--out-fs with float" "only with --arith q15" "${SIM[@]}" --arith float --out-fs 1
expect_err "q15 without full scales" "needs --in-fs and --out-fs" "${SIM[@]}" --arith q15 --in-fs 1
expect_err "q15 zero full scale" "--out-fs must be > 0" "${SIM[@]}" --arith q15 --in-fs 1 --out-fs 0
expect_err "--set unknown name" "unknown parameter 'gamma'" "${SIM[@]}" --set gamma=1
expect_err "--set without =" "expected NAME=VALUE" "${SIM[@]}" --set beta
expect_err "--set non-numeric" "--set beta: '0.8x' is not a finite number" "${SIM[@]}" --set beta=0.8x
expect_err "--set NaN" "not a finite number" "${SIM[@]}" --set beta=nan
expect_err "--set of a design option" "'fs' is not a model parameter" "${SIM[@]}" --set fs=1
expect_err "--set unused by the config" "does not use 'RCd'" "${SIM[@]}" --set RCd=0.01
expect_err "--set twice" "--set beta given more than once" "${SIM[@]}" --set beta=0.5 --set beta=0.6
expect_err "invalid parameter value" "invalid parameter 'beta' .*1.5" "${SIM[@]}" --set beta=1.5
# The refusal says what to give: the range when the value is outside its
# own, the other parameter's value when it is refused against that one.
expect_err "invalid parameter value names the range" "'beta' .*1.5.*outside \(0, 1\]" \
  "${SIM[@]}" --set beta=1.5
expect_err "inconsistent pid restrictors" "invalid parameter 'RC[di]'" simulate --config pid \
  --fs 1000 --duration 1 --set RCd=1 --set RCi=0.1
expect_err "inconsistent pid restrictors name the rule and the other one" \
  "'RCd' .*breaks RCd < RCi, with RCi = 0.1; change --set RCd=VALUE or --set RCi=VALUE" \
  simulate --config pid --fs 1000 --duration 1 --set RCd=1 --set RCi=0.1
expect_err "pmin above pmax names the rule and pmin" \
  "'pmax' .*breaks pmin <= pmax, with pmin = 20; change --set pmax=VALUE or --set pmin=VALUE" \
  "${SIM[@]}" --set pmin=20
expect_err "pid nu above w names the rule" "'w' .*breaks nu <= w, with nu = 0.9" \
  simulate --config pid --fs 1000 --duration 1 --set nu=0.9 --set w=0.5
expect_err "bellows compliance out of bounds names the rule and A" \
  "'ks' .*breaks 1/1e12 <= A/ks <= 1e12, with A = 1000000000" "${SIM[@]}" --set A=1e9 --set ks=1e-4
# Refused by the design, not by a rule (the in-sample loop nearly singular at
# this rate with RCd < RCi holding): no rule is claimed broken.
expect_err "a design refusal claims no broken rule" \
  "'RCd' .*cannot realise at --fs 0.1" simulate --config pid --fs 0.1 --duration 200 \
  --set RCd=1 --set RCi=2 --set nu=0.05 --set w=1 --set k1=1e3
expect_err "bad band syntax" "--band: expected WB:WH" "${SIM[@]}" --band 1-100
expect_err "band upside down" "--band: need 0 < WB < WH" "${SIM[@]}" --band 100:1
expect_err "band above Nyquist" "invalid parameter 'wh'" "${SIM[@]}" --band 1:1e6
expect_err "order not an integer" "--order: '2.5'" "${SIM[@]}" --order 2.5
expect_err "order out of range" "--order: '0'" "${SIM[@]}" --order 0
expect_err "unknown approx" "unknown method 'pade'" "${SIM[@]}" --approx pade
expect_err "unknown input model" "unknown model 'cubic'" "${SIM[@]}" --input-model cubic
expect_err "bad t-slow" "--t-slow must be > 0" "${SIM[@]}" --t-slow -1
expect_err "newline in an argument stays one line" "unknown configuration" \
  simulate --config $'d\nd' --fs 1000 --duration 1
expect_err "demo: unknown argument" "demo: unexpected argument" demo --fs 1

# --- output errors ------------------------------------------------------------
if [ -w /dev/full ]; then
  "$BIN" "${SIM[@]}" >/dev/full 2>"$TMP/err"
  rc=$?
  check "write error on stdout exits 1 with one message" \
    test "$rc" -eq 1 -a "$(wc -l <"$TMP/err")" -eq 1
  # bode's message said only "error writing the CSV": the reason too
  "$BIN" bode --config dd --fs 1000 --points 100000 >/dev/full 2>"$TMP/err"
  rc=$?
  check "bode: write error names the reason, in one line" \
    test "$rc" -eq 1 -a "$(wc -l <"$TMP/err")" -eq 1
  check "bode: write error names the reason" grep -q "No space left on device" "$TMP/err"
  # help goes out at main's last fflush: its reason read from that flush
  "$BIN" --help >/dev/full 2>"$TMP/err"
  rc=$?
  check "help to a full disk exits 1 and names the reason" \
    test "$rc" -eq 1 -a "$(wc -l <"$TMP/err")" -eq 1
  check "help to a full disk: the flush's reason" grep -q "No space left on device" "$TMP/err"
fi
"$BIN" simulate --config dd --fs 20000 --duration 20 2>"$TMP/err" | head -n 1 >/dev/null
rc=${PIPESTATUS[0]}
check "closed pipe exits 1 (no SIGPIPE death)" test "$rc" -eq 1
check "closed pipe gives one message" grep -q "^pneufrac: error writing standard output" "$TMP/err"

# --- demo ---------------------------------------------------------------------
if (cd "$TMP" && "$BIN" demo >"$TMP/demo.txt" 2>"$TMP/err"); then
  ok "demo exits 0"
else
  bad "demo exits 0" "$(head -c 300 "$TMP/err")"
fi
check "demo writes example6.csv with 40001 rows" \
  bash -c '[ "$(head -n 1 "$1")" = "t,e,pc" ] && [ "$(($(grep -vc "^#" "$1") - 1))" -eq 40001 ]' _ "$TMP/example6.csv"
check "demo output equals simulate --config dd --fs 20000 --duration 2" \
  bash -c '"$1" simulate --config dd --fs 20000 --duration 2 | cmp -s - "$2"' _ "$BIN" "$TMP/example6.csv"
check "demo summary names the config, design and table" \
  bash -c 'grep -q "config dd" "$1" && grep -q "order N = " "$1" && grep -qE "^ +1 ms +[0-9]" "$1" &&
           grep -qE "^ +peak " "$1" && grep -qE "^ +final " "$1"' _ "$TMP/demo.txt"
check "demo --out writes the named file" \
  bash -c '"$1" demo --out "$2/other.csv" >/dev/null && cmp -s "$2/other.csv" "$2/example6.csv"' _ "$BIN" "$TMP"
"$BIN" demo --out "$TMP/no/such/dir.csv" >"$TMP/out" 2>"$TMP/err"
rc=$?
check "demo --out into a missing directory exits 1 with one message" \
  test "$rc" -eq 1 -a "$(wc -l <"$TMP/err")" -eq 1 -a ! -s "$TMP/out"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
