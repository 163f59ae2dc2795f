#!/bin/bash
# Weft on a real GPU: one prepared run on a machine with an NVIDIA driver (made by bundle.sh beside
# this file; the numbers of docs/bench/gpu_h100.md). Usage, in the repository root there:
#   bash .dev/run.sh OUTDIR [small|gpu|quick|amg|newton|passes|group|dress|body]
# small: tiny sizes, to try the script on llvmpipe; gpu: the GPU runs only (no CPU runs of the
# sample scenes, converged bench without its CPU columns), to fit a short lease; quick: the
# default passes only (bench_gpu, the solver tests, the scenes, sheet100's peers rows): ~3 min;
# amg: the GPU's multigrid (rotations and smoothed P; translations; P_tent) against block Jacobi (its tests, converged steps, the scenes, peers;
# the V-cycle's fused passes against a pass a step at 30 iterations fixed);
# newton: sewing, Newton, the line search, BDF2 and TR-BDF2 on the GPU (their tests, the hanging
# sheet's rollbacks at Newton 1 / 2 / 2 + search) and the crowd (weft bench crowd: N garments
# batched / unbatched); passes: PCG's folded passes (docs/bench/gpu_solve.md, "Fewer passes"): the
# solver test, passes a frame and a PCG iteration with ms a step on both kinds of passes, the
# multigrid's converged steps, the scenes (the chain forced: WEFT_GPU_SOLVE=passes): ~4 min;
# group: PCG in one work group against the chain (WEFT_GPU_SOLVE=group / passes; its tests,
# bench_gpu's ms and passes a frame at 256 to 2,500 particles, block Jacobi fixed and converged,
# the multigrid converged, the scenes with each preconditioner both ways): ~5 min. dress: the GPU dressing a body (the collider and
# self-collision and penalty-pair tests, the suit on its turning body on both backends (and its
# GPU-against-CPU test; the GPU once more with the multigrid's pair cross terms, WEFT_GPU_AMG_CROSS=1), and the seed's anchor:
# weft bench collide at 25,600 particles on a 20k-triangle body, CPU and GPU): ~6 min;
# body: a deforming body from a host GL buffer against host arrays (its tests: the body's passes
# and its sharp-feature pairs against core, the API's two paths, a box's pairs both ways; bench_body_gl: bytes moved, ms of each call and of a step,
# 2k to 80k triangles): ~1 min.
O=${1:-/tmp/out}; MODE=${2:-}; SMALL=; [ "$MODE" = small ] && SMALL=1
mkdir -p "$O"
R=$PWD
tar xJf .dev/libs.tar.xz -C .dev && tar xJf .dev/bins.tar.xz && mkdir -p build-dev/tests/tmp
export LD_LIBRARY_PATH=$R/.dev/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do [ -d $d ] && export LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$d; done
for j in /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json /usr/share/glvnd/egl_vendor.d/10_nvidia.json; do
  [ -f $j ] && { export __EGL_VENDOR_LIBRARY_FILENAMES=$j; break; }; done
mkdir -p /work; [ -e /work/main ] || ln -s "$R" /work/main
probe() { timeout 60 build-dev/tests/bench/bench_gpu --sizes 8 --frames 1 --skip-cpu > /tmp/probe.txt 2>&1 && grep -qi "nvidia" /tmp/probe.txt; }
{
  ls -la /dev/nvidia* /dev/dri 2>&1 | head; timeout 15 find / -xdev \( -name "libEGL_nvidia*" -o -name "10_nvidia.json" -o -name "libEGL.so*" \) 2>/dev/null | head
  if probe; then echo "probe: ok (default)"; else cat /tmp/probe.txt; export WEFT_EGL_DEVICE=0;
    if probe; then echo "probe: ok (WEFT_EGL_DEVICE=0)"; else cat /tmp/probe.txt; unset WEFT_EGL_DEVICE; mkdir -p .dev/glaside; mv .dev/lib/libEGL* .dev/lib/libGL* .dev/lib/libOpenGL* .dev/glaside/;
      if probe; then echo "probe: ok (system glvnd)"; else cat /tmp/probe.txt; echo "probe: FAILED"; fi; fi; fi
  grep -i "egl\|opengl" /tmp/probe.txt | head -3
} 2>&1 | tee "$O/0_probe.log"
grep -q "probe: FAILED" "$O/0_probe.log" && [ -z "$SMALL" ] && exit 1
if [ "$MODE" = amg ]; then   # the multigrid (gpu/solver/wg_amg.h) against block Jacobi, GPU only
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    for t in test_gpu_amg test_gpu_amg_smooth test_gpu_amg_warm; do
      timeout 90 build-dev/tests/$t > /tmp/ta.txt 2>&1; echo "$t rc=$?"; grep -v " ok$" /tmp/ta.txt; done
    timeout 90 build-dev/tests/test_gpu_amg_smooth rot > /tmp/ta.txt 2>&1; echo "test_gpu_amg_rot rc=$?"; grep -v " ok$" /tmp/ta.txt
    for pc in amg block_jacobi; do
      timeout 150 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 3 --tolerance 1e-4 --iterations 1000 --skip-cpu --precond $pc 2>&1
    done
    # the V-cycle's fused passes against a pass a step (WEFT_GPU_AMG_FUSE=0), 30 iterations fixed:
    # passes and ms a frame and passes a PCG iteration (docs/bench/gpu_solve.md, "Fewer passes a V-cycle")
    for f in 1 0; do
      WEFT_GPU_AMG_FUSE=$f timeout 120 build-dev/tests/bench/bench_gpu --sizes 32,100,316 --frames 3 --skip-cpu --precond amg 2>&1
    done
    # the multigrid without rotations (translations, smoothed P), and with P = P_tent, at the same sizes
    WEFT_GPU_AMG_ROT=0 timeout 150 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 3 --tolerance 1e-4 --iterations 1000 --skip-cpu --precond amg 2>&1
    WEFT_GPU_AMG_SMOOTH=0 timeout 150 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 3 --tolerance 1e-4 --iterations 1000 --skip-cpu --precond amg 2>&1
    # the rotations about the current positions (opt-in): the same sizes, its test, the dance's check
    WEFT_GPU_AMG_CURRENT=1 timeout 150 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 3 --tolerance 1e-4 --iterations 1000 --skip-cpu --precond amg 2>&1
    timeout 60 build-dev/tests/test_gpu_amg_current > /tmp/ta.txt 2>&1; echo "test_gpu_amg_current rc=$?"; grep -v " ok$" /tmp/ta.txt
    WEFT_GPU_AMG_CURRENT=1 timeout 200 build-dev/tests/test_cli_gpu_dance > /tmp/ta.txt 2>&1; echo "test_cli_gpu_dance (current) rc=$?"; tail -12 /tmp/ta.txt
    for sc in hanging_sheet flag tablecloth poncho_shoulders skirt_turning sweeping_sphere; do
      for pc in amg block_jacobi; do
        timeout 60 build-dev/weft run sample_scenes/$sc.json --frames 90 --quiet --stats /tmp/st.json --backend gpu --precond $pc > /dev/null 2>&1 &&
        python3 -c "import json;s=json.load(open('/tmp/st.json'));print('| $sc | $pc | %.2f | %s | %.1f | %s | %s |'%(s['ms_per_frame']['median'],s.get('solves'),s.get('iterations',{}).get('mean',0),s.get('not_converged'),s.get('rollbacks')))"
      done
    done
    timeout 90 build-dev/weft bench peers --backend gpu --scenes sheet100 --substeps 1,2 --preconds amg,block_jacobi --newton 1 --threads 1 --frames 30 --md "$O/e_peers.md" > /dev/null 2>&1
    grep "^| sheet100 | 10000" "$O/e_peers.md"; } 2>&1 | tee "$O/g_amg.md"
  exit 0
fi
if [ "$MODE" = newton ]; then   # sewing, Newton, line search, BDF2 / TR-BDF2 and batching on the GPU
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    for t in test_gpu_sew test_api_gpu_sew test_api_gpu_newton test_gpu_bdf2 test_api_gpu_bdf2 test_api_batch; do
      timeout 120 build-dev/tests/$t > /tmp/tn.txt 2>&1; echo "$t rc=$?"; grep -iE "fail|against|bound|rollback" /tmp/tn.txt | head -8
    done
    echo "| scene | newton | line search | ms/frame median | solves | rollbacks |"; echo "|---|---|---|---|---|---|"
    for sc in hanging_sheet flag; do
      for nl in "1 off" "2 off" "2 on"; do set -- $nl
        timeout 60 build-dev/weft run sample_scenes/$sc.json --frames 90 --quiet --stats /tmp/st.json --backend gpu --newton $1 --line-search $2 > /dev/null 2>&1 &&
        python3 -c "import json;s=json.load(open('/tmp/st.json'));print('| $sc | $1 | $2 | %.2f | %s | %s |'%(s['ms_per_frame']['median'],s.get('solves'),s.get('rollbacks')))"
      done
    done
    timeout 240 build-dev/weft bench crowd --backend gpu --frames 10 2>&1 | tail -20; } 2>&1 | tee "$O/h_newton_crowd.md"
  exit 0
fi
if [ "$MODE" = group ]; then   # PCG in one work group against the multi-pass chain
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    for t in test_gpu_group test_api_gpu_group test_gpu_group_amg; do
      timeout 120 build-dev/tests/$t > /tmp/tg.txt 2>&1; echo "$t rc=$?"; grep -E "particles|group vs|FAIL" /tmp/tg.txt
    done
    for form in trans tent; do   # the group's multigrid with translations (smoothed, P_tent); rotations above
      timeout 120 build-dev/tests/test_gpu_group_amg $form > /tmp/tg.txt 2>&1; echo "test_gpu_group_amg $form rc=$?"; grep -E "particles|group vs|FAIL" /tmp/tg.txt
    done
    for solve in group passes; do
      WEFT_GPU_SOLVE=$solve timeout 120 build-dev/tests/bench/bench_gpu --sizes 16,32,50 --frames 5 --skip-cpu 2>&1 | head -12
      WEFT_GPU_SOLVE=$solve timeout 120 build-dev/tests/bench/bench_gpu --sizes 16,32,50 --frames 5 --tolerance 1e-4 --iterations 1000 --skip-cpu 2>&1 | head -12
      # the multigrid's V-cycle in the group (pcg_group_amg.glsl) against its chain, converged
      WEFT_GPU_SOLVE=$solve timeout 120 build-dev/tests/bench/bench_gpu --sizes 16,32,50 --frames 5 --tolerance 1e-4 --iterations 1000 --skip-cpu --precond amg 2>&1 | head -12
    done
    echo "| scene | solve | ms/frame median | solves | iterations mean | rollbacks |"; echo "|---|---|---|---|---|---|"
    for pc in block_jacobi amg; do
      M="--backend gpu --precond $pc --integrator be --newton 1 --line-search off --threads 1"
      for sc in hanging_sheet flag tablecloth poncho_shoulders skirt_turning sweeping_sphere; do
        for solve in group passes; do
          WEFT_GPU_SOLVE=$solve timeout 60 build-dev/weft run sample_scenes/$sc.json --frames 90 --quiet --stats /tmp/st.json $M > /tmp/run.txt 2>&1 || { echo "| $sc | $pc $solve | FAILED $(tail -c 200 /tmp/run.txt | tr '\n' ' ') |"; continue; }
          python3 -c "import json;s=json.load(open('/tmp/st.json'));print('| $sc | $pc $solve | %.2f | %s | %.1f | %s |'%(s['ms_per_frame']['median'],s.get('solves'),s.get('iterations',{}).get('mean',0),s.get('rollbacks')))"
        done
      done
    done; } 2>&1 | tee "$O/q_group.md"
  exit 0
fi
if [ "$MODE" = dress ]; then   # mesh colliders, Newton with contacts and self-collision on the GPU
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    for t in test_gpu_mesh_contacts test_api_gpu_mesh test_gpu_newton_contacts test_api_gpu_newton_contacts test_gpu_self test_api_gpu_self test_gpu_trbdf2_contacts test_api_gpu_trbdf2_contacts test_api_auto test_gpu_pairs test_gpu_amg_cross test_cli_gpu_suit; do
      [ -x build-dev/tests/$t ] || continue
      timeout 120 build-dev/tests/$t > /tmp/tb.txt 2>&1; echo "$t rc=$?"; grep -iE "fail|against|crossing|rollback|pairs|contact" /tmp/tb.txt | head -6
    done
    echo "| backend | self-collision | newton | ms/frame median | collide | self | solve | rollbacks |"; echo "|---|---|---|---|---|---|---|---|"
    for bk in cpu gpu; do
      for sn in "on 1" "on 2" "off 1"; do set -- $sn
        timeout 150 build-dev/weft run sample_scenes/suit_on_body.json --frames 30 --quiet --stats /tmp/st.json --backend $bk --threads 16 --self-collision $1 --newton $2 > /tmp/run.txt 2>&1 || { echo "| $bk | $1 | $2 | FAILED $(tail -c 200 /tmp/run.txt | tr '\n' ' ') |"; continue; }
        python3 -c "import json;s=json.load(open('/tmp/st.json'));m=s.get('stage_ms',{});print('| $bk | $1 | $2 | %.2f | %s | %s | %s | %s |'%(s['ms_per_frame']['median'],m.get('collide'),m.get('self_collide'),m.get('solve'),s.get('rollbacks')))"
      done
    done
    # the GPU multigrid's pair cross terms (opt-in) against the row above without them
    WEFT_GPU_AMG_CROSS=1 timeout 150 build-dev/weft run sample_scenes/suit_on_body.json --frames 30 --quiet --stats /tmp/st.json --backend gpu --threads 16 --self-collision on --newton 1 > /tmp/run.txt 2>&1 && \
      python3 -c "import json;s=json.load(open('/tmp/st.json'));m=s.get('stage_ms',{});print('| gpu, WEFT_GPU_AMG_CROSS=1 (%.1f it./solve) | on | 1 | %.2f | %s | %s | %s | %s |'%(s['iterations']['mean'],s['ms_per_frame']['median'],m.get('collide'),m.get('self_collide'),m.get('solve'),s.get('rollbacks')))"
    # the self stage's proximity pass on the GPU-listed pairs (opt-in until timed here) against the rows above
    for px in off on; do
      WEFT_GPU_SELF_PROX=$px timeout 150 build-dev/weft run sample_scenes/suit_on_body.json --frames 30 --quiet --stats /tmp/st.json --backend gpu --threads 16 --self-collision on --newton 1 > /tmp/run.txt 2>&1 && \
        python3 -c "import json;s=json.load(open('/tmp/st.json'));m=s.get('stage_ms',{});print('| gpu, WEFT_GPU_SELF_PROX=$px | on | 1 | %.2f | %s | %s | %s | %s |'%(s['ms_per_frame']['median'],m.get('collide'),m.get('self_collide'),m.get('solve'),s.get('rollbacks')))"
    done
    timeout 60 build-dev/weft run sample_scenes/suit_on_body.json --frames 2 --backend auto 2>&1 | grep -E "^backend|^method"
    timeout 240 build-dev/weft bench collide --backend cpu,gpu --cloth 64,160 --body 20000 --settle 2 --frames 3 --threads 16 2>&1 | tail -12; } 2>&1 | tee "$O/d_dress.md"
  exit 0
fi
if [ "$MODE" = body ]; then   # weft_cloth_set_mesh_collider_gl_buffer against the array call
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    timeout 60 build-dev/tests/test_gpu_mesh_body > /tmp/tm.txt 2>&1; echo "test_gpu_mesh_body rc=$?"; grep -E "substep|FAIL" /tmp/tm.txt
    timeout 60 build-dev/tests/test_api_gpu_body_gl > /tmp/tb.txt 2>&1; echo "test_api_gpu_body_gl rc=$?"; grep -E "frames|ulp|replayed|FAIL" /tmp/tb.txt
    timeout 60 build-dev/tests/test_gpu_mesh_sharp > /tmp/ts.txt 2>&1; echo "test_gpu_mesh_sharp rc=$?"; grep -E "substep|FAIL" /tmp/ts.txt
    timeout 60 build-dev/tests/test_api_gpu_body_pairs > /tmp/tp.txt 2>&1; echo "test_api_gpu_body_pairs rc=$?"; grep -E "frames|replayed|FAIL" /tmp/tp.txt
    for k in 32 100 200; do timeout 120 build-dev/tests/bench/bench_body_gl --k $k --n 64 --frames 30 2>&1 | tail -1; done
  } 2>&1 | tee "$O/i_body.md"
  exit 0
fi
if [ "$MODE" = passes ]; then   # PCG's folded passes: counts and ms a step, the fused sums' test
  export WEFT_GPU_SOLVE=passes   # the chain, where the one-group solve would take the small sizes
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    timeout 90 build-dev/tests/test_gpu_solver > /tmp/ts.txt 2>&1; echo "test_gpu_solver rc=$?"
    grep -E "rows:|capped at|FAIL" /tmp/ts.txt
    for passes in compute fragment; do
      WEFT_GPU_PASSES=$passes timeout 150 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 5 --skip-cpu 2>&1
    done
    timeout 150 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 3 --tolerance 1e-4 --iterations 1000 --skip-cpu --precond amg 2>&1
    M="--backend gpu --precond block_jacobi --integrator be --newton 1 --line-search off --threads 1"
    for sc in hanging_sheet flag tablecloth poncho_shoulders skirt_turning sweeping_sphere; do
      timeout 30 build-dev/weft run sample_scenes/$sc.json --frames 90 --quiet --stats /tmp/st.json $M > /dev/null 2>&1 &&
      python3 -c "import json;s=json.load(open('/tmp/st.json'));print('| $sc | %.2f | %s | %.1f | %s |'%(s['ms_per_frame']['median'],s.get('solves'),s.get('iterations',{}).get('mean',0),s.get('rollbacks')))"
    done; } 2>&1 | tee "$O/p_passes.md"
  exit 0
fi
if [ "$MODE" = quick ]; then   # what fits the last minutes of a lease: the default passes only
  { nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1
    timeout 120 build-dev/tests/bench/bench_gpu --sizes 32,100,316,1000 --frames 5 2>&1
    for t in test_gpu_solver test_gpu_contacts test_gpu_mesh_contacts test_api_gpu_mesh test_api_gpu; do
      timeout 60 build-dev/tests/$t > /tmp/tc.txt 2>&1; echo "$t rc=$?"; grep -i "spmv\|fail\|checks" /tmp/tc.txt | head -5
    done
    M="--backend gpu --precond block_jacobi --integrator be --newton 1 --line-search off --threads 1"
    for sc in hanging_sheet flag tablecloth poncho_shoulders skirt_turning sweeping_sphere; do
      timeout 30 build-dev/weft run sample_scenes/$sc.json --frames 90 --quiet --stats /tmp/st.json $M > /dev/null 2>&1 &&
      python3 -c "import json;s=json.load(open('/tmp/st.json'));print('| $sc | %.2f | %s | %.1f | %s |'%(s['ms_per_frame']['median'],s.get('solves'),s.get('iterations',{}).get('mean',0),s.get('rollbacks')))"
    done
    timeout 60 build-dev/weft bench peers --backend gpu --scenes sheet100 --substeps 1,2 --preconds block_jacobi --newton 1 --threads 1 --frames 30 --md "$O/e_peers.md" > /dev/null 2>&1
    grep "^| sheet100 | 10000" "$O/e_peers.md"; } 2>&1 | tee "$O/q_quick.md"
  exit 0
fi
{
  date; uname -a; nproc; free -g | head -2
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv 2>&1
  echo "EGL vendor json: ${__EGL_VENDOR_LIBRARY_FILENAMES:-none}"; ls /usr/local/nvidia/lib64 2>/dev/null | grep -i "egl\|glx\|gldispatch" | head
  echo "--- missing libs:"; for b in build-dev/weft build-dev/tests/bench/bench_gpu; do ldd $b | grep "not found"; done
  echo "--- GPU tests"
  for t in test_api_gpu test_gpu_solver test_gpu_contacts test_gpu_mesh_contacts test_api_gpu_mesh test_render test_api_render test_render_errors test_cli_gpu_runs; do
    s=$(date +%s.%N); timeout 150 build-dev/tests/$t > "$O/t_$t.txt" 2>&1; rc=$?
    awk -v t=$t -v rc=$rc -v s=$s -v e=$(date +%s.%N) 'BEGIN{printf "%-20s rc=%d  %.1f s\n", t, rc, e-s}'
    [ $rc -ne 0 ] && tail -25 "$O/t_$t.txt"
  done
  grep -h "context\|device\|renderer\|OpenGL" "$O/t_test_api_gpu.txt" | head -8
  echo "--- test_cli_gpu_runs table"; grep "|" "$O/t_test_cli_gpu_runs.txt"
} 2>&1 | tee "$O/a_info_tests.log"
cat "$O"/t_*.txt > "$O/b_tests_full.log"; rm -f "$O"/t_*.txt
if [ -n "$SMALL" ]; then SZ=16,32; SZC=16; F=2; else SZ=32,100,316,1000; SZC=32,100,316; F=5; fi
# both kinds of passes (docs/design/gpu.md, "Compute-shader passes"; compute is the default on
# GL 4.3), one after the other
{ WEFT_GPU_PASSES=fragment timeout 240 build-dev/tests/bench/bench_gpu --sizes $SZ --frames $F 2>&1
  echo; WEFT_GPU_PASSES=compute timeout 240 build-dev/tests/bench/bench_gpu --sizes $SZ --frames $F 2>&1
  echo; echo "--- GPU tests with fragment passes"
  for t in test_gpu_solver test_gpu_contacts test_gpu_mesh_contacts test_api_gpu; do
    WEFT_GPU_PASSES=fragment timeout 150 build-dev/tests/$t > /tmp/tc.txt 2>&1; echo "$t (fragment) rc=$?"; tail -3 /tmp/tc.txt
  done; } 2>&1 | tee "$O/c_bench_gpu_30it.md"
# the sample scenes: ms/frame on the GPU, on the CPU with the GPU's method, and the CPU at its defaults
{
  echo "| scene | run | ms/frame median | solves | iterations mean | rollbacks | max strain |"; echo "|---|---|---|---|---|---|---|"
  FR=90; [ -n "$SMALL" ] && FR=3
  for sc in hanging_sheet flag tablecloth poncho_shoulders skirt_turning sweeping_sphere; do
    M="--precond block_jacobi --integrator be --newton 1 --line-search off"
    # name|WEFT_GPU_PASSES|weft run options
    for run in "gpu-fragment|fragment|--backend gpu $M --threads 1" "gpu-compute|compute|--backend gpu $M --threads 1" \
               "cpu-same-method-1t|fragment|--backend cpu $M --threads 1" "cpu-defaults-1t|fragment|--backend cpu --threads 1" \
               "cpu-defaults-16t|fragment|--backend cpu --threads 16"; do
      [ "$MODE" = gpu ] && [ "${run#cpu}" != "$run" ] && continue
      IFS='|' read -r name passes args <<< "$run"
      WEFT_GPU_PASSES=$passes timeout 120 build-dev/weft run sample_scenes/$sc.json --frames $FR --quiet --stats /tmp/st.json $args > /tmp/run.txt 2>&1 || { echo "| $sc | $name | FAILED rc=$? $(tail -c 300 /tmp/run.txt | tr '\n' ' ') |"; continue; }
      python3 -c "import json,sys;s=json.load(open('/tmp/st.json'));it=s.get('iterations',{});print('| $sc | $name | %.2f | %s | %.1f | %s | %.4f |'%(s['ms_per_frame']['median'],s.get('solves'),it.get('mean',0),s.get('rollbacks'),s.get('max_strain',0)))"
    done
  done
} 2>&1 | tee "$O/d_scenes.md"
PS=sheet100,sheet64; PF=30; [ -n "$SMALL" ] && PS=sheet16 && PF=3
for passes in compute fragment; do
  WEFT_GPU_PASSES=$passes timeout 400 build-dev/weft bench peers --backend gpu --scenes $PS --substeps 1,2,4 --preconds block_jacobi --newton 1 --threads 1 --frames $PF --md "$O/e_peers_$passes.md" 2>&1 | tail -30
done
SKIP=; [ "$MODE" = gpu ] && SKIP=--skip-cpu
for passes in compute fragment; do
  echo "WEFT_GPU_PASSES=$passes"
  WEFT_GPU_PASSES=$passes timeout 200 build-dev/tests/bench/bench_gpu --sizes $SZC --frames 3 --tolerance 1e-4 --iterations 3000 $SKIP 2>&1
done | tee "$O/f_bench_gpu_converged.md"
echo done
