#!/usr/bin/env bash
# Do two builds of `weft` give the same results? For a change that must not change any result (a
# restructuring): every bundled sample scene is run by both binaries, on the CPU and on the GPU
# backend (llvmpipe where there is no GPU), and the OBJ frames must be byte-identical and the
# statistics JSON identical once the wall-clock fields (every key starting with "ms", and
# "stage_ms*") are dropped.
#
#   bash .ci/same_results.sh OLD_WEFT NEW_WEFT [FRAMES] [WORK_DIR]
#
# FRAMES defaults to 30. codimipc_dance reads ../shared (not bundled) and costs seconds a frame: it
# runs only when ../shared is there, for at most 3 frames. Prints one
# line per run and exits 1 on the first difference's report (all runs are still made).
set -uo pipefail
cd "$(dirname "$0")/.."

old=${1:?usage: same_results.sh OLD_WEFT NEW_WEFT [FRAMES] [WORK_DIR]}
new=${2:?usage: same_results.sh OLD_WEFT NEW_WEFT [FRAMES] [WORK_DIR]}
frames=${3:-30}
work=${4:-$(mktemp -d)}
mkdir -p "$work"

strip_ms() {   # the stats JSON without wall-clock fields, keys sorted
  python3 - "$1" <<'PY'
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not (k == "ms" or k.startswith("ms_") or k.startswith("stage_ms"))}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(open(sys.argv[1]))), sort_keys=True, indent=1))
PY
}

fail=0
for scene in sample_scenes/*.json; do
  name=$(basename "$scene" .json)
  n=$frames
  if [ "$name" = codimipc_dance ]; then
    [ -e ../shared/meshes/codimipc_dance ] || continue
    [ "$n" -gt 3 ] && n=3
  fi
  for backend in cpu gpu; do
    for which in old new; do
      bin=$old; [ "$which" = new ] && bin=$new
      out="$work/$which/$name.$backend"
      rm -rf "$out" && mkdir -p "$out"
      OMP_WAIT_POLICY=passive "$bin" run "$scene" --frames "$n" --quiet --threads 1 --backend "$backend" \
        --out "$out/obj" --stats "$out/stats.json" >"$out/log" 2>&1
      echo $? >"$out/rc"
    done
    a="$work/old/$name.$backend" b="$work/new/$name.$backend"
    verdict=same
    if ! cmp -s "$a/rc" "$b/rc"; then
      verdict="exit status $(cat "$a/rc") -> $(cat "$b/rc")"
    elif [ "$(cat "$a/rc")" != 0 ]; then
      verdict="refused by both (exit $(cat "$a/rc"))"
      cmp -s "$a/log" "$b/log" || verdict="$verdict, different messages"
    elif ! diff -rq "$a/obj" "$b/obj" >/dev/null; then
      verdict="OBJ frames differ: $(diff -rq "$a/obj" "$b/obj" | head -n 1)"
    elif ! diff <(strip_ms "$a/stats.json") <(strip_ms "$b/stats.json") >"$work/$name.$backend.diff"; then
      verdict="statistics differ ($work/$name.$backend.diff)"
    fi
    case "$verdict" in same|"refused by both"*) ;; *) fail=1 ;; esac
    printf '%-20s %-4s %3s frames: %s\n' "$name" "$backend" "$n" "$verdict"
  done
done
exit $fail
