#!/bin/bash
# Packs what docs/bench/gpu_device/run.sh needs on a GPU machine that has an NVIDIA driver but
# none of Weft's Debian libraries (the lent H100 of 2026-11-27: an image with CUDA, no apt):
# the built binaries, and every shared library they load except glibc's and the C++ runtime,
# Debian's GLVND (libEGL, libGL, libOpenGL) included. Run from the repository root after
#   cmake -S . -B build-dev -DCMAKE_BUILD_TYPE=Release && cmake --build build-dev -j2
# (the test binaries hold /work/main/... paths: run.sh links /work/main to the copy there).
# Output: .dev/libs.tar.xz, .dev/bins.tar.xz, .dev/run.sh (ignore .dev in .git/info/exclude and
# carry it).
set -e
B=build-dev
LIB=$(ls $B/plugin/libweft.so.*.*.*)   # the versioned file (libweft.so.ABI.MINOR.PATCH)
SONAME=$(ls $B/plugin/libweft.so.* | grep -E 'libweft\.so\.[0-9]+$')
BINS="$B/weft $LIB $B/tests/test_gpu_solver $B/tests/test_gpu_amg $B/tests/test_gpu_contacts $B/tests/test_api_gpu
      $B/tests/test_gpu_sew $B/tests/test_api_gpu_sew $B/tests/test_api_gpu_newton $B/tests/test_api_batch
      $B/tests/test_gpu_bdf2 $B/tests/test_api_gpu_bdf2 $B/tests/test_gpu_mesh_contacts $B/tests/test_api_gpu_mesh
      $B/tests/test_cli_gpu_runs $B/tests/test_render $B/tests/test_api_render $B/tests/test_render_errors
      $B/tests/test_gpu_group $B/tests/test_api_gpu_group $B/tests/test_api_gpu_body_gl $B/tests/test_gpu_mesh_body
      $B/tests/test_gpu_newton_contacts $B/tests/test_api_gpu_newton_contacts $B/tests/test_gpu_self
      $B/tests/test_api_gpu_self $B/tests/test_gpu_trbdf2_contacts $B/tests/test_api_gpu_trbdf2_contacts
      $B/tests/test_api_auto $B/tests/test_gpu_pairs $B/tests/test_gpu_amg_cross $B/tests/test_cli_gpu_suit $B/tests/test_gpu_group_amg $B/tests/test_gpu_amg_smooth
      $B/tests/bench/bench_gpu $B/tests/bench/bench_render $B/tests/bench/bench_body_gl"
T=$(mktemp -d)
mkdir -p "$T/lib" .dev
for b in $BINS; do ldd "$b" | awk '$3 ~ /^\//{print $1, $3}'; done | sort -u |
    grep -v '^libc\.so\|^libm\.so\|libweft\|ld-linux\|libstdc++\|libgcc_s\|libpthread\|libdl\.so\|librt\.so' |
    while read -r so path; do cp -L "$path" "$T/lib/$so"; done
tar cJf .dev/libs.tar.xz -C "$T" lib
rm -rf "$T"
tar cJf .dev/bins.tar.xz $BINS $B/plugin/libweft.so $SONAME
cp docs/bench/gpu_device/run.sh .dev/run.sh
ls -la .dev
