#!/usr/bin/env bash
# Draw time of the SVG mesh script (formats/svg/script/mesh_polyfill.js) in headless Chromium:
# a whole image (fruits, --segment: ~24,000 patches) converted to the default SVG, opened with
# window.gradmeshMeshOptions = {timing: true}, so that the script prints the time it took to
# find, parse, tessellate, draw and paint every mesh; read from Chromium's log. Runs RUNS times
# each: the default (on SwiftShader the script uses its canvas 2D path), WebGL forced
# ({noWebGL: false}: WebGL on SwiftShader) and the canvas 2D path ({noWebGL: true}).
# Usage: bash bench/browser_draw.sh [RUNS]   (outputs under bench-out/browser/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
gm=build/app/gradmesh
out=bench-out/browser
mkdir -p "$out"
[ -f "$out/fruits.gmb" ] || $gm convert samples/fruits.jpg --segment -o "$out/fruits.gmb" >/dev/null
$gm convert "$out/fruits.gmb" -o "$out/fruits.svg"
$gm info "$out/fruits.gmb" | grep -E "^(canvas|patches):"
echo "script: $(wc -c < build/formats/svg/generated/mesh_polyfill.min.js) bytes minified"
for mode in default webgl 2d; do
  options='{timing:true}'
  [ $mode = webgl ] && options='{timing:true,noWebGL:false}'
  [ $mode = 2d ] && options='{timing:true,noWebGL:true}'
  # The options go in a script before the meshes, right after the root element's start tag.
  python3 - "$out/fruits.svg" "$out/fruits_$mode.svg" "$options" <<'PY'
import sys
svg = open(sys.argv[1]).read()
at = svg.index('>', svg.index('<svg ')) + 1
open(sys.argv[2], 'w').write(svg[:at] + '<script>window.gradmeshMeshOptions=' + sys.argv[3] +
                             '</script>' + svg[at:])
PY
  for run in $(seq "$runs"); do
    rm -rf "$out/profile"
    chromium --headless --no-sandbox --disable-gpu-sandbox --use-angle=swiftshader \
      --enable-unsafe-swiftshader --hide-scrollbars --force-device-scale-factor=1 --no-first-run \
      --disable-extensions --user-data-dir="$PWD/$out/profile" --enable-logging=stderr --v=0 \
      --virtual-time-budget=60000 --window-size=512,480 --screenshot="$PWD/$out/fruits_$mode.png" \
      "file://$PWD/$out/fruits_$mode.svg" 2>&1 | grep -o '"gradmesh [^"]*"' | head -1
  done
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
