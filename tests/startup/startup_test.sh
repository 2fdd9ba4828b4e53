#!/usr/bin/env bash
# startup_test.sh GRADMESH WORK_DIR: see CMakeLists.txt.
set -euo pipefail
gm=$1 work=$2
rm -rf "$work"
mkdir -p "$work"
image_libs='libopencv|libOpenImageIO'

fail() { echo "startup test: $*" >&2; exit 1; }

# The shared libraries a run of the command loads, by the dynamic loader's own account.
loaded_libs() { LD_DEBUG=libs "$@" 2>&1 >/dev/null | grep -o 'calling init: [^ ]*' || true; }

# Nothing the launcher needs at start names an image library.
if ldd "$gm" | grep -E "$image_libs"; then fail "$gm links an image library"; fi

# Inputs: the built-in sample as .gmb and SVG (written by gradmesh-imaging), and a Hermite
# mesh, whose info refits its colours.
"$gm" sample "$work/sample.gmb"
"$gm" sample "$work/sample.svg"
"$gm" convert "$work/sample.gmb" -o "$work/sample-copy.gmb"

# The check itself sees the image libraries where they are loaded.
loaded_libs "$gm" sample "$work/control.gmb" | grep -qE "$image_libs" ||
  fail "LD_DEBUG shows no image library for 'sample': the check would see nothing"

for run in "--help" "--version" "convert --help" "info $work/sample.gmb" "info $work/sample.svg"; do
  # shellcheck disable=SC2086
  libs=$(loaded_libs "$gm" $run)
  [ -n "$libs" ] || fail "LD_DEBUG shows nothing for 'gradmesh $run'"
  if grep -E "$image_libs" <<<"$libs"; then fail "'gradmesh $run' loads an image library"; fi
done
"$gm" info "$work/sample.gmb" | grep -q "^meshes: [1-9]" || fail "info of a .gmb prints no meshes"
"$gm" info "$work/sample.svg" | grep -q "^format: svg" || fail "info of an SVG"

# A launcher without gradmesh-imaging: help and info still work; a command that needs it fails
# with a message naming it, exit 1, and writes nothing.
mkdir -p "$work/alone"
cp "$gm" "$work/alone/gradmesh"
"$work/alone/gradmesh" info "$work/sample.gmb" >/dev/null
set +e
"$work/alone/gradmesh" convert "$work/sample.gmb" -o "$work/alone/out.svg" 2>"$work/alone/err"
code=$?
set -e
[ "$code" = 1 ] || fail "convert without gradmesh-imaging exits $code, not 1"
grep -q "gradmesh convert: cannot start gradmesh-imaging" "$work/alone/err" ||
  fail "unexpected message: $(cat "$work/alone/err")"
[ ! -e "$work/alone/out.svg" ] || fail "convert without gradmesh-imaging wrote its output"
echo "startup test: passed"
