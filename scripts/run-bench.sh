#!/usr/bin/env bash
# Runs every benchmark binary of the bench build with JSON output, then writes
# docs/benchmarks.md and the charts (scripts/bench_report.py) and the figure of
# docs/rendering.md (scripts/render_figures.py). HEDRA_BENCH_QUICK=1: smaller inputs, a shorter
# minimum time per benchmark and 3 repetitions instead of 5 (make bench-quick, < 5 minutes).
# `run-bench.sh --perturbation BUILD`: only the perturbation study of decompose_bench, which
# rewrites only that section of docs/benchmarks.md and its chart.
set -euo pipefail
# Huge pages for every benchmark process, hedra's and its peers' alike: the hedra command sets
# glibc's tunable for itself (cli/main.cpp, use_huge_pages), the benchmark binaries get it here.
# GLIBC_TUNABLES=glibc.malloc.hugetlb=0 in the environment keeps 4 KB pages.
case "${GLIBC_TUNABLES:-}" in
  *glibc.malloc.hugetlb*) ;;
  "") export GLIBC_TUNABLES=glibc.malloc.hugetlb=1 ;;
  *) export GLIBC_TUNABLES="$GLIBC_TUNABLES:glibc.malloc.hugetlb=1" ;;
esac
if [ "${1:-}" = "--perturbation" ]; then
  build=${2:-build-bench}
  mkdir -p "$build/results-perturbation"
  "$build/decompose_bench" --benchmark_filter='^perturbed/' --benchmark_format=console \
    --benchmark_out="$build/results-perturbation/decompose_bench.json" --benchmark_out_format=json
  /usr/bin/python3 scripts/bench_report.py --perturbation "$build/results-perturbation" docs
  exit 0
fi
build=${1:-build-bench}
out="$build/results"
mkdir -p "$out"
reps=5
flags=()
if [ -n "${HEDRA_BENCH_QUICK:-}" ]; then
  reps=3
  flags+=(--benchmark_min_time=0.05)
fi
start=$SECONDS
for bin in "$build"/*_bench; do
  [ -x "$bin" ] || continue
  name=$(basename "$bin")
  t0=$SECONDS
  echo "== $name"
  "$bin" --benchmark_format=console --benchmark_out="$out/$name.json" --benchmark_out_format=json \
    --benchmark_repetitions=$reps "${flags[@]}"
  echo "== $name: $((SECONDS - t0)) s"
done
if [ -x "$build/hedra" ]; then
  # Faces scaling: whole processes of the command at t = 1e-2 ... 1e-5 and a 1 M-triangle mesh.
  t0=$SECONDS
  echo "== faces scaling (scripts/faces_scaling.py)"
  /usr/bin/python3 scripts/faces_scaling.py "$build/hedra" "$out" ${HEDRA_BENCH_QUICK:+--quick}
  echo "== faces scaling: $((SECONDS - t0)) s"
fi
echo "== all benchmarks: $((SECONDS - start)) s"
/usr/bin/python3 scripts/bench_report.py "$out" docs
if [ -x "$build/hedra" ]; then /usr/bin/python3 scripts/render_figures.py "$build/hedra" docs; fi
