#!/usr/bin/env bash
# Runs the benchmarks and appends the results, with the machine and the commands, to
# bench/RESULTS.md. Usage: bash bench/run.sh BUILD_DIR
set -euo pipefail
build=${1:-build}
here=$(cd "$(dirname "$0")" && pwd)
out="$here/RESULTS.md"
stamp=$(date -u +%Y-%m-%dT%H:%M:%SZ)
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
{
  echo
  echo "## $stamp — $(nproc) cores, $cpu"
  echo
  echo "Command: \`make bench\` ($build/bench/bench_model; $build/woven drape cube --threads 1; bench/drape_matrix.sh)"
  echo
  echo '```'
  "$build/bench/bench_model" --benchmark_min_time=0.5 2>&1 | grep -E '^(Benchmark|---|[a-z_]+ )'
  echo '```'
  echo
  echo "End to end, the paper's cube (1 m, 51 x 51, cotton, fast solver, one thread):"
  echo
  echo '```'
  /usr/bin/time -f 'wall %e s, max RSS %M KiB' "$build/woven" drape cube --threads 1 --no-render --out "$build/bench-out" 2>&1 | grep -vE '^\s*(step|\[)' | tail -12
  echo '```'
  echo
  echo "Every built-in fabric on the built-in scenes (fast solver, one thread; bench/drape_matrix.sh):"
  echo
  bash "$here/drape_matrix.sh" "$build"
} >> "$out"
echo "bench: results appended to $out"
