#!/usr/bin/env bash
# Configure and build one build folder: bash .ci/build.sh DIR [extra cmake arguments...]
# .ci/demo and .ci/test share build/ with the same arguments, so running one after the other
# rebuilds nothing. WEFT_WERROR=ON in the environment (as .ci/run sets it) makes warnings errors.
set -euo pipefail
cd "$(dirname "$0")/.."

dir=$1
shift
cmake -S . -B "$dir" -DWEFT_WERROR="${WEFT_WERROR:-OFF}" "$@"
cmake --build "$dir" -j"$(nproc)"
