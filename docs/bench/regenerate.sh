#!/usr/bin/env bash
# Regenerate the `weft bench` tables and plots of docs/bench/ (summarised in docs/bench/README.md)
# and gpu.md with a Release build of this checkout:
#
#   cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j
#   bash docs/bench/regenerate.sh [BUILD_DIR] [THREADS]
#
# About 3 h on a 2-core machine (an estimate: the preconditioner, integrator and Newton axes
# double the last full run's 1.5 h), most of it `weft bench accuracy`: its reference runs at 32
# substeps per frame and again at 64 (the check that it is converged in time: halving its step
# must move it by < 0.1 % of the bounding-box diagonal; at 8 substeps backward Euler misses that
# by ~3x), and PCG runs with both preconditioners. sheet256 is left out of accuracy (alone about
# an hour; add it with --scenes) but is in `weft bench iterations`. Run it on an otherwise idle
# machine: every ms/frame is a wall-clock median. `weft bench peers` needs Debian's blender (it
# prints Weft's rows alone without it); bench_hypre is built only where hypre is installed
# (libhypre-dev).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
threads=${2:-2}
weft="$build/weft"
[ -x "$weft" ] || { echo "regenerate.sh: $weft not found: build first (see the top of this file)" >&2; exit 1; }
export OMP_WAIT_POLICY=passive
out="$here"

# run time against error: every solver, PCG with block_jacobi and amg (the default --preconds)
"$weft" bench accuracy --scenes sheet32,sheet64,sheet100,drape,garment --threads "$threads" --ref-substeps 32 \
  --csv "$out/accuracy.csv" --md "$out/accuracy.md" --plot "$out/accuracy.png"
# the methods at the library's settings (tolerance 1e-4, cap 300): preconditioner x
# integrator x Newton iterations (line search on with 3), 1 and 2 substeps per frame
"$weft" bench accuracy --scenes sheet32,sheet64,sheet100,drape,garment --threads "$threads" --ref-substeps 32 \
  --solvers pcg,direct --tolerances 1e-4 --iterations 300 --substeps 1,2 --preconds all --integrators all \
  --newton 1,3 --csv "$out/accuracy_methods.csv" --md "$out/accuracy_methods.md" --plot "$out/accuracy_methods.png"
# iterations per solve: sheets 32^2..256^2, stiffness x1..x1e4 on 64^2, drape, garment; the goals
"$weft" bench iterations --threads "$threads" --csv "$out/iterations.csv" --md "$out/iterations.md"
"$weft" bench stability --threads "$threads" \
  --csv "$out/stability.csv" --md "$out/stability.md" --plot "$out/stability.png"
"$weft" bench skip --threads 1 --csv "$out/skip.csv" --md "$out/skip.md"
# collision detection's cost over cloth (1k..100k particles) and body (1k..80k triangles) sizes,
# self-collision on; the goal row at 160 x 160 (hours on a loaded 2-core machine: the 100k sheet)
OPENBLAS_NUM_THREADS=1 "$weft" bench collide --threads 1 --settle 3 --frames 3 \
  --csv "$out/collide.csv" --md "$out/collide.md"
"$weft" bench peers --threads 1 --csv "$out/peers.csv" --md "$out/peers.md"
"$weft" bench torture --threads 1 --md "$out/torture_run.md"
python3 "$here/pareto.py" "$out/accuracy.csv" > "$out/accuracy_pareto.md"
python3 "$here/pareto.py" "$out/accuracy_methods.csv" > "$out/accuracy_methods_pareto.md"
# the GPU backend beside the CPU backend, 1k to 1M particles (on llvmpipe without a GPU: minutes)
"$build/tests/bench/bench_gpu" --sizes 32,100,316,1000 --frames 5 > "$out/gpu.md"
# Weft's preconditioners beside hypre's BoomerAMG on single substep systems (where hypre is installed)
if [ -x "$build/tests/bench/bench_hypre" ]; then
  OPENBLAS_NUM_THREADS=1 "$build/tests/bench/bench_hypre" --sizes 32,64,128,256 --threads 1 > "$out/hypre.md"
else
  echo "regenerate.sh: $build/tests/bench/bench_hypre not built (no hypre: apt-get install libhypre-dev): hypre.md not rewritten" >&2
fi
