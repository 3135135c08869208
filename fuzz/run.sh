#!/usr/bin/env bash
# Runs each fuzz target for FUZZ_SECONDS (default 60) on its corpus: the committed regression
# corpus fuzz/corpus/<target>/ and the built-in files as seeds; new inputs go to
# <build>/fuzz-corpus/<target>/, crashes to <build>/fuzz-artifacts/. Usage: run.sh BUILD [SECONDS] [TARGETS...]
set -uo pipefail
build=${1:?usage: run.sh BUILD [SECONDS] [TARGETS...]}
seconds=${2:-60}
shift $(( $# >= 2 ? 2 : $# ))
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(fabric scene obj gltf values corner_map output_set output_json sweep_plan glb_check start shadow)
root=$(cd "$(dirname "$0")/.." && pwd)
# Seeds are folders (libFuzzer runs a file argument once and stops); the corner map's are its
# corpus, which holds a small valid map (docs/experiments' are 50 kB, over -max_len).
declare -A seeds=([fabric]="$root/fabrics" [scene]="$root/scenes" [obj]="$root/assets" [gltf]="$root/assets $root/fuzz/corpus/obj"
                  [values]="" [corner_map]="" [output_set]="" [output_json]="" [sweep_plan]="$root/examples" [glb_check]="" [start]="" [shadow]="")
declare -A dicts=([fabric]="-dict=$root/fuzz/toml.dict" [scene]="-dict=$root/fuzz/toml.dict" [obj]="-dict=$root/fuzz/obj.dict"
                  [gltf]="-dict=$root/fuzz/obj.dict" [values]="-dict=$root/fuzz/values.dict" [corner_map]="-dict=$root/fuzz/json.dict" [output_set]=""
                  [output_json]="-dict=$root/fuzz/json.dict" [sweep_plan]="-dict=$root/fuzz/toml.dict" [glb_check]="" [start]="-dict=$root/fuzz/obj.dict" [shadow]="")
# Per-input time limits: 20 s; a sweep plan may hold 10^6 values (1 s in Release, about 25 s
# instrumented on the shared 2-core machine: slow, not a hang).
declare -A timeouts=([sweep_plan]=90)
status=0
for t in "${targets[@]}"; do
  work="$build/fuzz-corpus/$t"
  mkdir -p "$work" "$build/fuzz-artifacts"
  echo "fuzz_$t: ${seconds} s" >&2
  log="$build/fuzz-$t.log"
  "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout="${timeouts[$t]:-20}" -rss_limit_mb=4096 -max_len=16384 \
    ${dicts[$t]} -print_final_stats=1 -artifact_prefix="$build/fuzz-artifacts/$t-" \
    "$work" "$root/fuzz/corpus/$t" ${seeds[$t]} > "$log" 2>&1 || { status=1; grep -A3 "ERROR\|deadly\|Test unit" "$log" >&2; }
  # The last coverage line and the final counts (the whole log is in $log).
  grep -E "^#[0-9]+" "$log" | tail -n 1 >&2
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" "$log" >&2
done
exit $status
