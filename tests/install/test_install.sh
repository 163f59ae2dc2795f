#!/bin/sh
# test_install: `cmake --install` the build into a fresh prefix, check the installed files, then
# build tests/install/consumer outside the tree twice -- with find_package(weft) and with
# pkg-config -- run both and check their output against the backward-Euler free fall.
# Usage: test_install.sh BUILD_DIR WORK_DIR CMAKE CC LIBDIR CONSUMER_SRC [EXTRA_CFLAGS]
set -eu
build=$1 work=$2 cmake=$3 cc=$4 libdir=$5 src=$6 extra=${7:-}
prefix=$work/prefix
rm -rf "$work"
mkdir -p "$work"
fail() { echo "test_install: FAILED: $*" >&2; exit 1; }

"$cmake" --install "$build" --prefix "$prefix" > "$work/install.log" || fail "cmake --install"
for f in include/weft/weft.h include/weft/weft_status.h "$libdir/libweft.so" \
         "$libdir/libweft.so.10" "$libdir/pkgconfig/weft.pc" "$libdir/cmake/weft/weftConfig.cmake" \
         "$libdir/cmake/weft/weftConfigVersion.cmake" "$libdir/cmake/weft/weftTargets.cmake" \
         bin/weft share/weft/host_glue/loader/weft_loader.c share/weft/host_glue/python/weft/__init__.py \
         share/weft/host_glue/python/weft/_abi.py share/weft/host_glue/python/pyproject.toml \
         share/weft/host_glue/python/setup.py \
         share/weft/host_glue/blender/weft_blender.py; do
  [ -e "$prefix/$f" ] || fail "not installed: $f"
done
[ -L "$prefix/$libdir/libweft.so" ] || fail "libweft.so is not the development symlink"
real=$(readlink -f "$prefix/$libdir/libweft.so")
case $real in */libweft.so.10.*) ;; *) fail "libweft.so -> $real, expected libweft.so.10.x.y" ;; esac
soname=$(readelf -d "$real" | sed -n 's/.*Library soname: \[\(.*\)\].*/\1/p')
[ "$soname" = libweft.so.10 ] || fail "SONAME '$soname', expected libweft.so.10"
echo "installed: $(cd "$prefix" && find . -type f -o -type l | sort | tr '\n' ' ')"
echo "SONAME $soname"

# The free-fall check: 16 vertices, x and z as at rest, y = 1 - g h^2 N (N + 1) / 2.
check_output() {
  awk -v name="$1" '
    /^weft / { if ($4 != $7) { print name ": library ABI " $4 " != header ABI " $7; bad = 1 } }
    /^v / { n++; i = $2; x0 = 0.1 * (i % 4); z0 = 0.1 * int(i / 4)
            y = 1 - 9.81 / 3600 * 10 * 11 / 2
            if ((x0 - $3)^2 > 1e-10 || (z0 - $5)^2 > 1e-10 || (y - $4)^2 > 1e-8) {
              print name ": vertex " i " at " $3 " " $4 " " $5 ", expected " x0 " " y " " z0; bad = 1 } }
    END { if (n != 16) { print name ": " n " vertices, expected 16"; bad = 1 }
          if (!bad) print name ": 16 vertices fell " 9.81 / 3600 * 55 " m as backward Euler predicts"
          exit bad }' "$2"
}

# 1. CMake: find_package(weft) from the prefix.
"$cmake" -S "$src" -B "$work/cmake_consumer" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_C_COMPILER="$cc" -DCMAKE_C_FLAGS="$extra" > "$work/cmake_consumer.log" 2>&1 ||
  { cat "$work/cmake_consumer.log"; fail "configuring the find_package consumer"; }
grep "weft .* from " "$work/cmake_consumer.log" || true
"$cmake" --build "$work/cmake_consumer" > "$work/cmake_build.log" 2>&1 ||
  { cat "$work/cmake_build.log"; fail "building the find_package consumer"; }
"$work/cmake_consumer/weft_consumer" > "$work/cmake_consumer.out" || fail "find_package consumer run"
ldd "$work/cmake_consumer/weft_consumer" | grep -q "$prefix/$libdir/libweft.so.10" ||
  fail "the find_package consumer does not load the installed libweft.so.10"
check_output find_package "$work/cmake_consumer.out"

# An incompatible version request is refused (0.x: same minor only).
if "$cmake" -S "$src" -B "$work/cmake_consumer_v1" -DCMAKE_PREFIX_PATH="$prefix" \
     -DWEFT_REQUIRED_VERSION=1.0 > "$work/cmake_consumer_v1.log" 2>&1; then
  fail "find_package(weft 1.0) accepted version 0.10"
fi
grep -q "weftConfigVersion.cmake\|version: 0.10" "$work/cmake_consumer_v1.log" ||
  fail "find_package(weft 1.0) failed without naming the version"

# 2. pkg-config, with a plain compiler line.
export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig"
[ "$(pkg-config --modversion weft)" = "$(sed -n 's/^Version: //p' "$prefix/$libdir/pkgconfig/weft.pc")" ] ||
  fail "pkg-config --modversion"
pc_libdir=$(pkg-config --variable=libdir weft)
[ "$(readlink -f "$pc_libdir")" = "$(readlink -f "$prefix/$libdir")" ] || fail "pkg-config libdir $pc_libdir"
# shellcheck disable=SC2046,SC2086
"$cc" -std=c11 -Wall -Wextra -Wpedantic -Werror $extra "$src/weft_consumer.c" \
  $(pkg-config --cflags weft) -o "$work/pc_consumer" $(pkg-config --libs weft) \
  -Wl,-rpath,"$pc_libdir" || fail "building the pkg-config consumer"
"$work/pc_consumer" > "$work/pc_consumer.out" || fail "pkg-config consumer run"
check_output pkg-config "$work/pc_consumer.out"
cmp -s "$work/cmake_consumer.out" "$work/pc_consumer.out" || fail "the two consumers disagree"
head -n 2 "$work/pc_consumer.out"
echo "test_install: ok"
