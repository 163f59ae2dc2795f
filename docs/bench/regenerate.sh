#!/usr/bin/env bash
# Regenerate every table and plot in docs/bench/ (and so in the README's "Performance and
# accuracy" section) with a Release build of this checkout:
#
#   cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j
#   bash docs/bench/regenerate.sh [BUILD_DIR] [THREADS]
#
# About 1.5 h on a 2-core machine, most of it `weft bench accuracy` (sheet256 is left out: it
# alone takes about an hour; add it with --scenes). Run it on an otherwise idle machine: every
# ms/frame is a wall-clock median. `weft bench peers` needs Debian's blender.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
threads=${2:-2}
weft="$build/weft"
[ -x "$weft" ] || { echo "regenerate.sh: $weft not found: build first (see the top of this file)" >&2; exit 1; }
export OMP_WAIT_POLICY=passive
out="$here"

"$weft" bench accuracy --scenes sheet32,sheet64,sheet100,drape,garment --threads "$threads" \
  --csv "$out/accuracy.csv" --md "$out/accuracy.md" --plot "$out/accuracy.png"
"$weft" bench stability --threads "$threads" \
  --csv "$out/stability.csv" --md "$out/stability.md" --plot "$out/stability.png"
"$weft" bench skip --threads 1 --csv "$out/skip.csv" --md "$out/skip.md"
"$weft" bench peers --threads 1 --csv "$out/peers.csv" --md "$out/peers.md"
"$weft" bench torture --threads 1 --md "$out/torture_run.md"
python3 "$here/pareto.py" "$out/accuracy.csv" > "$out/accuracy_pareto.md"
# the GPU backend beside the CPU backend, 1k to 1M particles (on llvmpipe without a GPU: minutes)
"$build/tests/bench/bench_gpu" --sizes 32,100,316,1000 --frames 5 > "$out/gpu.md"
