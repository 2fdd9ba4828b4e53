#!/usr/bin/env bash
# install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR: see CMakeLists.txt.
set -euo pipefail
build=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >"$work/install.log"
for f in bin/gradmesh libexec/gradmesh/gradmesh-imaging include/gradmesh/gradmesh.h lib/cmake/gradmesh/gradmeshConfig.cmake \
         lib/pkgconfig/gradmesh.pc lib/libgradmesh_meshcore.a share/man/man1/gradmesh.1 \
         share/bash-completion/completions/gradmesh; do
  [ -e "$prefix/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done
# Nothing installed may point back into the source or build tree.
if grep -rl -e "$src" -e "$build" "$prefix/lib/cmake" "$prefix/lib/pkgconfig"; then
  echo "the installed package refers to the source or build tree" >&2
  exit 1
fi

# The man page reads, and the completion defines its function for gradmesh.
MANPATH="$prefix/share/man" LC_ALL=C.UTF-8 man -P cat gradmesh 2>/dev/null | grep -q -- "--output-dir" ||
  { echo "man gradmesh does not show the installed page" >&2; exit 1; }
bash -c "source '$prefix/share/bash-completion/completions/gradmesh' && complete -p gradmesh" | grep -q _gradmesh ||
  { echo "the installed completion does not complete gradmesh" >&2; exit 1; }

echo "== find_package(gradmesh)"
cmake -S "$src/examples" -B "$work/cmake-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log"
cmake --build "$work/cmake-build" >"$work/build.log"
"$work/cmake-build/convert" "$src/samples/horse.png" "$work/horse.svg"
"$prefix/bin/gradmesh" info "$work/horse.svg" | grep -E "^meshes: [1-9]"
# The installed command finds gradmesh-imaging for the commands that need the image libraries.
"$prefix/bin/gradmesh" render "$work/horse.svg" -o "$work/horse-render.png"
[ -s "$work/horse-render.png" ] || { echo "the installed gradmesh rendered nothing" >&2; exit 1; }

echo "== pkg-config gradmesh"
flags=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs gradmesh)
# shellcheck disable=SC2086
g++ -std=c++17 -O1 "$src/examples/convert.cpp" -o "$work/convert-pc" $flags
"$work/convert-pc" "$src/samples/horse.png" "$work/horse-pc.svg"
cmp "$work/horse.svg" "$work/horse-pc.svg"
echo "install test: passed"
