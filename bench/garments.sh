#!/bin/sh
# The garment examples (examples/garments, issue 54) in two fabrics at two spacings: each run's
# wall time (the solver's, report.json wall_time_s, all stages), the whole process's elapsed
# time and peak RSS (GNU time), the hem measures and the seam gaps, one JSON line per run in
# $OUT/runs.jsonl. Usage: bench/garments.sh [WOVEN] [OUT] [SPACINGS] [THREADS]; EXAMPLES and FABRICS
# in the environment pick fewer examples or other fabrics.
set -eu
WOVEN=${1:-build/woven}
OUT=${2:-out/bench-garments}
SPACINGS=${3:-"2 1"}
THREADS=${4:-2}
mkdir -p "$OUT"
for spacing in $SPACINGS; do
  for threads in $THREADS; do
    for example in ${EXAMPLES:-circular-skirt gored-skirt-straight gored-skirt-bias tube-skirt}; do
      for fabric in ${FABRICS:-silk denim}; do
        dir="$OUT/$example-$fabric-$spacing-t$threads"
        load=$(cut -d' ' -f1 /proc/loadavg)
        /usr/bin/time -f '%e %U %M' -o "$dir.time" "$WOVEN" garment "examples/garments/$example.toml" --fabric "$fabric" \
          --spacing "$spacing" --threads "$threads" --out "$dir" --quiet > "$dir.log" 2>&1 || echo "failed: $dir" >&2
        python3 - "$dir" "$example" "$fabric" "$spacing" "$threads" "$load" <<'PY'
import json, sys
d, example, fabric, spacing, threads, load = sys.argv[1:]
r = json.load(open(d + "/report.json"))
elapsed, user, rss_kib = open(d + ".time").read().split()[-3:]
print(json.dumps({"example": example, "fabric": fabric, "spacing_cm": float(spacing), "threads": int(threads),
                  "particles": r["particles"], "converged": r["converged"], "steps": r["steps"],
                  "solver_s": round(r["wall_time_s"], 2), "elapsed_s": float(elapsed), "user_cpu_s": float(user), "peak_rss_mib": round(int(rss_kib) / 1024),
                  "hem_nodes": r["hem"]["nodes"], "flare": round(r["hem"]["flare"], 4),
                  "below_waist_cm": round(100 * r["hem"]["below_waist_m"], 2), "length_drop_cm": round(100 * r["hem"]["length_drop_m"], 2),
                  "seam_gap_over_spacing": round(r["seam_max_gap_over_spacing"], 5), "load_before": float(load)}))
PY
      done
    done
  done
done | tee -a "$OUT/runs.jsonl"
