#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite: unit tests, malformed-input
# suites, the [external] checks with Inkscape, Ghostscript and poppler, and the .gmb and SVG
# reader fuzzers (libFuzzer under AddressSanitizer + UndefinedBehaviorSanitizer, bounded time).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh

echo "== fuzzer build (clang, ASan+UBSan)"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DGRADMESH_FUZZ=ON >/dev/null
ninja -C build-fuzz gmb_fuzzer svg_fuzzer

echo "== build (Release)"
bash scripts/build.sh -DGRADMESH_FUZZER="$PWD/build-fuzz/tests/fuzz/gmb_fuzzer" \
  -DGRADMESH_SVG_FUZZER="$PWD/build-fuzz/tests/fuzz/svg_fuzzer" \
  -DGRADMESH_FUZZ_SECONDS="${GRADMESH_FUZZ_SECONDS:-60}"

echo "== tests"
cd build
ctest --output-on-failure --timeout 900 -j"$(nproc)"
