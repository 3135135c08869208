#!/usr/bin/env bash
# The Cusick drape test over the built-in fabric library (docs/CUSICK.md), run as a sweep
# (docs/SWEEP-FORMAT.md): the plan examples/cusick-library.toml (every built-in fabric x seeds
# 1..K), resumed where an earlier run stopped, then one table row per fabric from sweep.json: DC
# mean and std over the seeds, DC and nodes per run, wall time of its points.
#   scripts/cusick_library.sh [WOVEN] [SEEDS] [SPACING_CM] [OUT] [JOBS]
# Defaults: build/woven, 5 seeds, the default spacing, out/cusick-library, 1 job. With other
# seeds or a spacing the plan is written to OUT/plan.toml. Run it niced on a shared machine:
# nice -n 19 scripts/cusick_library.sh. On a cluster, run the plan with mpirun or a Slurm array
# instead (docs/CLI.md, "woven sweep") and print the table with: scripts/cusick_library.sh WOVEN 5 "" OUT
# after `woven sweep PLAN --out OUT --merge` (every point done: nothing runs again).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
woven=${1:-build/woven}
seeds=${2:-5}
spacing=${3:-}
out=${4:-out/cusick-library}
jobs=${5:-1}
mkdir -p "$out"
plan="$here/examples/cusick-library.toml"
if [ "$seeds" != 5 ] || [ -n "$spacing" ]; then
  plan="$out/plan.toml"
  sed -e "s/^seed = .*/seed = {from = 1, to = $seeds}/" "$here/examples/cusick-library.toml" > "$plan"
  [ -n "$spacing" ] && sed -i -e "s/^\[options\]/[options]\nspacing_cm = $spacing/" "$plan"
fi
"$woven" sweep "$plan" --out "$out" --jobs "$jobs" >&2
python3 - "$out/sweep.json" <<'PY'
import json, statistics, sys
j = json.load(open(sys.argv[1]))
rows = {}
for r in j["rows"]:
    rows.setdefault(r["values"]["fabric"], []).append(r)
print("| fabric | DC mean % | DC std | DC per run | nodes per run | wall s (all runs) |\n|---|---|---|---|---|---|")
for fabric, rs in rows.items():
    done = [r for r in rs if r["status"] == "done"]
    if len(done) < len(rs):
        print(f"| {fabric} | {len(rs) - len(done)} of {len(rs)} points not done | | | | |")
        continue
    dc = [r["outputs"]["drape_coefficient_percent"] for r in done]
    std = statistics.stdev(dc) if len(dc) > 1 else 0.0
    conv = "" if all(r["outputs"]["converged"] for r in done) else " (not all converged)"
    print(f"| {fabric} | {statistics.mean(dc):.1f} | {std:.1f} | {' '.join(f'{d:.1f}' for d in dc)} | "
          f"{' '.join(str(r['outputs']['nodes']) for r in done)} | {sum(r['wall_time_s'] for r in done):.0f}{conv} |")
PY
