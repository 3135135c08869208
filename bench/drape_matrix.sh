#!/usr/bin/env bash
# Drapes every built-in fabric over the built-in scenes (fast solver, one thread) and prints a
# Markdown table of the reports. Usage: bash bench/drape_matrix.sh BUILD_DIR [SCENES...]
set -uo pipefail
build=${1:-build}
shift || true
scenes=("$@")
[[ ${#scenes[@]} -gt 0 ]] || scenes=(cube table chair)
fabrics=$("$build/woven" fabrics | awk 'NR > 2 && NF { print $1 }')
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { grep -m1 "\"$1\":" "$2" | sed -E 's/.*: *//; s/,$//'; }
echo "| scene | fabric | grid | converged | steps | Newton its | factorisations | wall (s) | energy (J) | residual (m g) | penetration (m) | strain max |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  for fabric in $fabrics; do
    dir="$out/$scene-$fabric"
    "$build/woven" drape "$scene" --fabric "$fabric" --threads 1 --no-render --out "$dir" > /dev/null 2>&1
    rc=$?
    r="$dir/report.json"
    if [[ ! -f $r ]]; then echo "| $scene | $fabric | | exit $rc | | | | | | | | |"; continue; fi
    grid=$(tr -d ' \n' < "$r" | sed -E 's/.*"grid":\[([0-9]+),([0-9]+)\].*/\1 x \2/')
    echo "| $scene | $fabric | $grid | $(field converged "$r") | $(field steps "$r") | $(field iterations "$r") | $(field factorizations "$r") | $(printf %.1f "$(field wall_time_s "$r")") | $(printf %.4f "$(field total_J "$r")") | $(printf %.2g "$(field max_residual_rel "$r")") | $(printf %.2g "$(field max_penetration_m "$r")") | $(printf %.4f "$(field max "$r")") |"
  done
done
