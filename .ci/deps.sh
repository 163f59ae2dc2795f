#!/usr/bin/env bash
# Install the Debian 12 packages Weft needs to build and test. Called by .ci/demo and .ci/test
# (`bash .ci/deps.sh`). As root: apt-get installs whatever is missing. Otherwise: prints the
# apt-get line to run and exits 1. Does nothing when everything is already installed.
set -euo pipefail

packages=(
  gcc g++ make cmake pkg-config   # toolchain (g++ only because assimp's CMake config wants CXX)
  libassimp-dev                   # mesh import
  zlib1g-dev                      # FBX's deflated arrays (core/fbx_geometry.c)
  libsuitesparse-dev              # CHOLMOD
  libopenblas0-pthread            # fast BLAS behind CHOLMOD (switches libblas.so.3)
  libglew-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri   # GPU backend, headless EGL
  libpng-dev                      # preview renderer: PNG output (gpu/png_write.c)
  libcjson-dev                    # JSON (weft inspect --json, scene files)
  python3-numpy                   # host_glue/python bindings and their tests (/usr/bin/python3)
  python3-pip python3-venv python3-setuptools python3-wheel   # pip install ./host_glue/python, offline
  godot3-server                   # the Godot plugin's test (tests/godot): headless Godot 3.2, ~21 MB
  blender                         # the add-on test (tests/blender) and `weft bench peers`: ~480 MB, ~25 s to install
  libplplot-dev plplot-driver-cairo   # weft bench plots (PLplot, pngcairo device)
  libhypre-dev                    # tests/bench/bench_hypre only (BoomerAMG beside Weft's preconditioners):
                                  # brings OpenMPI, ~15 MB download / 67 MB installed; never linked into
                                  # libweft.so or the weft CLI, and the build skips bench_hypre without it
  clang libclang-rt-14-dev        # .ci/fuzz (libFuzzer, ASan, UBSan) and .ci/tsan (ThreadSanitizer)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "weft: missing Debian packages: ${missing[*]}" >&2
  echo "Install them with:" >&2
  echo "  sudo apt-get install -y --no-install-recommends ${missing[*]}" >&2
  exit 1
fi

echo "weft: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update
apt-get install -y --no-install-recommends "${missing[@]}"
