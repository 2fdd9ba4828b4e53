#!/usr/bin/env bash
# The conversion benchmark in one command: prints the paper's Table 1 for the bundled and
# synthetic inputs (Markdown, on stdout; progress on stderr). See bench/README.md.
#
#   bash bench/run.sh [BUILD_DIR]        (default: build; relative to the repository root)
#
# BUILD_DIR is built (Release) if it has no gradmesh binary: build/ through scripts/build.sh,
# any other directory with cmake + ninja. The bench tools (make_samples, jpeg_match) are built
# in it when missing. Environment: BENCH_REPEAT (runs per row, default 1), BENCH_BIG (side of
# the upscaled apple, default 4096; 0 skips that row), BENCH_ONLY (rows whose label contains
# it), BENCH_NO_COLORS=1 (skip the fit vs sampled table), BENCH_TIMEOUT (s per conversion).
# After Table 1, the whole-image rate-distortion section against JPEG (bench/whole.py):
# BENCH_NO_WHOLE=1 skips it, BENCH_ONLY_WHOLE=1 runs only it, BENCH_WHOLE_POINTS=2,8,2/25 sets
# its points (E = --max-error E; E/P = --max-error E --max-patches P; E/tN = --max-error E
# --total-patches N).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac

if [ ! -x "$build/app/gradmesh" ]; then
  if [ "$(realpath -m "$build")" = "$(realpath -m "$root/build")" ]; then
    echo "== building $build (scripts/build.sh)" >&2
    bash scripts/build.sh >&2
  else
    echo "== building $build (Release)" >&2
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
    ninja -C "$build" gradmesh >&2
  fi
fi
if [ ! -x "$build/bench/make_samples" ] || [ ! -x "$build/bench/jpeg_match" ] ||
   ! { "$build/bench/jpeg_match" 2>&1 || true; } | grep -q -- --curve; then  # older: no --curve
  echo "== building the bench tools in $build" >&2
  ninja -C "$build" make_samples jpeg_match >&2
fi

args=(--build "$build" --repeat "${BENCH_REPEAT:-1}" --big "${BENCH_BIG:-4096}"
      --only "${BENCH_ONLY:-}" --timeout "${BENCH_TIMEOUT:-3600}")
[ -n "${BENCH_NO_COLORS:-}" ] && args+=(--no-colors)
[ -n "${BENCH_NO_WHOLE:-}" ] && args+=(--no-whole)
[ -n "${BENCH_ONLY_WHOLE:-}" ] && args+=(--whole)
[ -n "${BENCH_WHOLE_POINTS:-}" ] && args+=("--whole-points=$BENCH_WHOLE_POINTS")
exec python3 bench/run.py "${args[@]}"
