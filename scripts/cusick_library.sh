#!/usr/bin/env bash
# The Cusick drape test over the built-in fabric library (docs/CUSICK.md): for each fabric,
# `woven cusick FABRIC --seeds K` and one table row: DC mean and std, nodes per run, wall time.
#   scripts/cusick_library.sh [WOVEN] [SEEDS] [SPACING_CM] [OUT]
# Defaults: build/woven, 5 seeds, the default spacing, out/cusick-library. Run it niced on a
# shared machine: nice -n 19 scripts/cusick_library.sh
set -euo pipefail
woven=${1:-build/woven}
seeds=${2:-5}
spacing=${3:-}
out=${4:-out/cusick-library}
mkdir -p "$out"
fabrics=$("$woven" fabrics --json | python3 -c 'import json,sys; print(" ".join(f["name"] for f in json.load(sys.stdin)))')
printf '| fabric | DC mean %% | DC std | nodes per run | wall s (all runs) |\n|---|---|---|---|---|\n'
for f in $fabrics; do
  args=("$f" --seeds "$seeds" --threads 1 --no-render --out "$out/$f")
  [ -n "$spacing" ] && args+=(--spacing-cm "$spacing")
  start=$(date +%s.%N)
  "$woven" cusick "${args[@]}" > "$out/$f.log" 2> "$out/$f.err"
  end=$(date +%s.%N)
  python3 - "$out/$f/cusick.json" "$f" "$start" "$end" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
mean = j.get("drape_coefficient_mean", j["drape_coefficient_percent"])
std = j.get("drape_coefficient_std", 0.0)
nodes = j.get("nodes_per_run", [j["nodes"]])
conv = "" if j["converged"] else " (not all converged)"
print(f"| {sys.argv[2]} | {mean:.1f} | {std:.1f} | {' '.join(map(str, nodes))} | {float(sys.argv[4]) - float(sys.argv[3]):.0f}{conv} |")
PY
done
