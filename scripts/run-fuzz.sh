#!/usr/bin/env bash
# Runs every libFuzzer target of tests/fuzz for SECONDS each, starting from the seed corpus in
# tests/fuzz/corpus/<target>/ (never modified: new inputs go to BUILD/corpus/<target>/).
# Any finding (crash, sanitizer report, timeout, out-of-memory, unexpected exception) stops the
# run with a non-zero exit and leaves the input in BUILD/findings/. Prints executions per second
# and corpus sizes per target.
# HEDRA_FUZZ_SEED=N fixes libFuzzer's random seed (CI does, so that a run on another machine
# walks the same inputs, as far as its speed allows, and a finding can be replayed); unset or 0:
# a new seed every run (make fuzz).
# Usage: scripts/run-fuzz.sh BUILD_DIR SECONDS [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
seconds=${2:-60}
shift 2 || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(stl obj off ply scene segments commands solid); fi
seed_option=()
if [ "${HEDRA_FUZZ_SEED:-0}" != 0 ]; then seed_option=(-seed="$HEDRA_FUZZ_SEED"); fi
mkdir -p "$build/findings"
printf '%-10s %8s %10s %12s %14s\n' target seconds "exec/s" "corpus files" "corpus bytes"
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  mkdir -p "$work"
  log="$build/fuzz-$t.log"
  # -timeout: one input may take at most 10 s; -rss_limit_mb: 2 GB; inputs up to 64 KB.
  if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0 UBSAN_OPTIONS=print_stacktrace=1 \
      "$build/fuzz_$t" "${seed_option[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/findings/$t-" \
      "$work" "tests/fuzz/corpus/$t" > "$log" 2>&1; then
    echo "fuzz: $t found a problem; the log is $log, the input in $build/findings/:" >&2
    grep -E "ERROR|SUMMARY|Test unit written|what\(\)|rejects its own" "$log" | head -20 >&2
    exit 1
  fi
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  files=$(find "$work" -type f | wc -l)
  bytes=$(du -sb "$work" | cut -f1)
  printf '%-10s %8s %10s %12s %14s\n' "$t" "$seconds" "$rate" "$files" "$bytes"
done
