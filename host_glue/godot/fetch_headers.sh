#!/usr/bin/env bash
# Fetch Godot 3.2.3's GDNative C headers from Debian's `godot3` source package and generate
# gdnative_api_struct.gen.h with the package's own generator.
#
#   host_glue/godot/fetch_headers.sh DEST
#
# apt runs on a private configuration under DEST/apt (a deb-src entry in a file of its own, its
# own lists and cache): the system's sources and lists are untouched, and no root is needed.
# DEST/include then holds the headers (gdnative/, nativescript/, ..., gdnative_api_struct.gen.h).
# Does nothing when DEST/include/gdnative_api_struct.gen.h is already there.
set -euo pipefail

dest=${1:?usage: fetch_headers.sh DEST}
mirror=${WEFT_DEBIAN_MIRROR:-http://deb.debian.org/debian}
suite=bookworm
version=3.2.3-stable
mkdir -p "$dest"
dest=$(cd "$dest" && pwd)
include="$dest/include"
if [ -f "$include/gdnative_api_struct.gen.h" ]; then
  exit 0
fi

apt_dir="$dest/apt"
mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$apt_dir/source"
echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror $suite main" \
  > "$apt_dir/sources.list"
apt_opts=(
  -o "Dir::Etc::sourcelist=$apt_dir/sources.list"
  -o "Dir::Etc::sourceparts=$apt_dir/no-parts"
  -o "Dir::State::Lists=$apt_dir/lists"
  -o "Dir::Cache=$apt_dir/cache"
  -o "Debug::NoLocking=1"
  -o "APT::Sandbox::User=$(id -un)"
  -qq
)
apt-get "${apt_opts[@]}" update
# The package's source is godot (godot3 is its binary); Debian adds no patches to it.
(cd "$apt_dir/source" && apt-get "${apt_opts[@]}" source --download-only "godot3=$version-1")

orig="$apt_dir/source/godot_$version.orig.tar.gz"
top="godot-$version"
tree="$dest/tree"
rm -rf "$tree" && mkdir -p "$tree"
tar -xzf "$orig" -C "$tree" --strip-components=1 \
  "$top/LICENSE.txt" "$top/platform_methods.py" \
  "$top/modules/gdnative/include" "$top/modules/gdnative/gdnative_api.json" \
  "$top/modules/gdnative/gdnative_builders.py"

# What modules/gdnative/SCsub does: build_gdnative_api_struct(targets, [gdnative_api.json]).
python3 - "$tree" <<'PY'
import sys
tree = sys.argv[1]
sys.path[:0] = [tree, tree + "/modules/gdnative"]
import gdnative_builders
gd = tree + "/modules/gdnative/"
gdnative_builders.build_gdnative_api_struct(
    [gd + "include/gdnative_api_struct.gen.h", gd + "gdnative_api_struct.gen.cpp"],
    [gd + "gdnative_api.json"], None)
PY

rm -rf "$include.tmp" && cp -r "$tree/modules/gdnative/include" "$include.tmp"
cp "$tree/LICENSE.txt" "$include.tmp/LICENSE.txt"
mv "$include.tmp" "$include"
echo "godot: GDNative headers of Godot $version in $include"
