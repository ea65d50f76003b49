#!/usr/bin/env bash
# Runs every benchmark binary of the bench build with JSON output, then writes
# docs/benchmarks.md and the charts (scripts/bench_report.py).
set -euo pipefail
build=${1:-build-bench}
out="$build/results"
mkdir -p "$out"
for bin in "$build"/*_bench; do
  [ -x "$bin" ] || continue
  name=$(basename "$bin")
  echo "== $name"
  reps=5
  [ -n "${HEDRA_BENCH_QUICK:-}" ] && reps=3
  "$bin" --benchmark_format=console --benchmark_out="$out/$name.json" --benchmark_out_format=json \
    --benchmark_repetitions=$reps
done
/usr/bin/python3 scripts/bench_report.py "$out" docs
