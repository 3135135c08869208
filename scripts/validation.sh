#!/bin/sh
# The measured-drape validation set (docs/validation/README.md): runs every fabric of
# docs/validation/measured.csv through `woven cusick` (one thread, niced) and writes
# docs/validation/table.md, results.json and dc_measured_vs_simulated.png.
#   scripts/validation.sh [extra options of scripts/validation.py, e.g. --set main --reuse]
# WOVEN (default build/woven) and SEEDS (default 3) may be set in the environment.
set -eu
cd "$(dirname "$0")/.."
exec nice -n 19 /usr/bin/python3 scripts/validation.py --woven "${WOVEN:-build/woven}" --seeds "${SEEDS:-3}" "$@"
