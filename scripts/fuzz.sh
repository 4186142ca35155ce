#!/usr/bin/env bash
# Fuzzes every file loader with libFuzzer (clang, ASan + UBSan + LeakSanitizer):
#
#   bash scripts/fuzz.sh [SECONDS] [--runs N] [--targets "rig model ..."] [--jobs J] [--json]
#
# Each target runs until N executions (default 1,000,000) or SECONDS
# (default 600) have passed, whichever comes first; a hang is an input that
# takes over 1 s. Targets: tests/fuzz/fuzz_targets.cpp. Seeds are written by
# the project's own writers (facesr_fuzz_seeds) plus the start of each real
# Live Link take in ../shared/data/livelink when present; inputs that once
# broke a target (tests/fuzz/regressions/<target>/) are added to its corpus.
# The corpus grows in out/fuzz/corpus/<target> and is kept between runs.
# Anything found is written to out/fuzz/findings/<target>/ and fails the run:
# copy it to tests/fuzz/regressions/<target>/ with a name saying what it
# found, fix the loader, and the test suite replays it from then on.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

seconds=600 runs=1000000 jobs=$(nproc) json=0 only=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --targets) only=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --json) json=1; shift ;;
    [0-9]*) seconds=$1; shift ;;
    *) echo "fuzz.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

bash scripts/install-deps.sh
out=$root/out/fuzz
build=$root/build-fuzz
CXX=clang++ cmake -S tests/fuzz -B "$build" -DCMAKE_BUILD_TYPE=None >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null

all=$(sed -n 's/^foreach(t \([a-z_ ]*\)).*/\1/p' tests/fuzz/CMakeLists.txt)
targets=${only:-$all}
for t in $targets; do
  [[ " $all " == *" $t "* ]] || { echo "fuzz.sh: no target '$t' (targets: $all)" >&2; exit 2; }
done

livelink=${FACESR_LIVELINK_DIR:-$root/../shared/data/livelink}
rm -rf "$out/seeds"
"$build/facesr_fuzz_seeds" "$out/seeds" "$livelink" >&2

export FACESR_FUZZ_TMP=$out/tmp
mkdir -p "$FACESR_FUZZ_TMP"
# Each target's run in the background, at most $jobs at once.
fuzz_one() {
  local t=$1 log=$out/logs/$t.log
  mkdir -p "$out/corpus/$t" "$out/findings/$t" "$out/logs"
  local dirs=("$out/corpus/$t" "$out/seeds/$t")
  [[ -d tests/fuzz/regressions/$t ]] && dirs+=("tests/fuzz/regressions/$t")
  local rc=0
  ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0" \
  UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1" \
    "$build/fuzz_$t" "${dirs[@]}" -runs="$runs" -max_total_time="$seconds" -timeout=1 \
      -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
      -artifact_prefix="$out/findings/$t/" >"$log" 2>&1 || rc=$?
  echo $rc >"$out/logs/$t.rc"
}

t0=$SECONDS
n=$(wc -w <<<"$targets") i=0 running=0
rm -f "$out"/logs/*.rc 2>/dev/null || true
for t in $targets; do
  i=$((i + 1))
  echo "fuzz: [$i/$n] $t (until $runs runs or ${seconds} s; $((SECONDS - t0)) s so far, at most $(( (n - i + 1) * seconds / jobs )) s left)" >&2
  fuzz_one "$t" &
  running=$((running + 1))
  if [[ $running -ge $jobs ]]; then wait -n; running=$((running - 1)); fi
done
wait

status=0 rows=()
printf '%-16s %10s %8s %9s %8s %s\n' target executions seconds exec/s findings result >&2
for t in $targets; do
  log=$out/logs/$t.log rc=$(cat "$out/logs/$t.rc")
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  secs=$(sed -n 's/^stat::.*//; s/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
  execs=${execs:-0} secs=${secs:-$seconds}
  findings=$(find "$out/findings/$t" -type f | wc -l)
  crashes=$(find "$out/findings/$t" -name 'crash-*' | wc -l)
  leaks=$(find "$out/findings/$t" -name 'leak-*' | wc -l)
  hangs=$(find "$out/findings/$t" -name 'timeout-*' -o -name 'slow-unit-*' | wc -l)
  ooms=$(find "$out/findings/$t" -name 'oom-*' | wc -l)
  result=ok
  if [[ $rc != 0 || $findings != 0 ]]; then result="FAILED (exit $rc, see $log)"; status=1; fi
  if [[ $execs -lt $runs && $result == ok ]]; then result="ok, short of $runs runs"; fi
  printf '%-16s %10s %8s %9s %8s %s\n' "$t" "$execs" "$secs" "$(( execs / (secs > 0 ? secs : 1) ))" "$findings" "$result" >&2
  rows+=("\"$t\": {\"executions\": $execs, \"seconds\": $secs, \"crashes\": $crashes, \"leaks\": $leaks, \"hangs_over_1s\": $hangs, \"out_of_memory\": $ooms, \"exit_code\": $rc}")
done
rm -rf "$FACESR_FUZZ_TMP"
if [[ $json == 1 ]]; then
  (IFS=,; echo "{\"ok\": $([[ $status == 0 ]] && echo true || echo false), \"runs_goal\": $runs, \"seconds_cap\": $seconds, \"targets\": {${rows[*]}}}")
fi
exit $status
