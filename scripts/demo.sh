#!/usr/bin/env bash
# Installs what is missing, builds (Release), and runs the main job on a bundled sample:
# the outputs land in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
gm=build/converters/gradmesh
set -x
# Until raster conversion lands, the sample is built programmatically: two meshes, one with 3 holes.
$gm sample out/sample.gmb
$gm info out/sample.gmb
$gm convert out/sample.gmb -o out/sample-compact.gmb --compact
$gm convert out/sample.gmb -o out/sample.svg                      # exact colours, for Inkscape
$gm convert out/sample.gmb -o out/sample-editable.svg --svg-colors editable
$gm convert out/sample.gmb -o out/sample.eps
$gm convert out/sample.gmb -o out/sample.pdf
$gm convert out/sample.gmb -o out/sample-legacy.pdf --legacy       # holes as hole-free pieces
$gm render out/sample.gmb -o out/sample.png --background white
$gm render out/sample.gmb -o out/sample@4x.png --scale 4
$gm render out/sample-compact.gmb -o out/sample-compact.png --background white
$gm compare out/sample.png out/sample-compact.png
set +x
ls -l out
