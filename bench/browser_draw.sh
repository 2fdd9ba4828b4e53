#!/usr/bin/env bash
# Draw time of the SVG mesh script (formats/svg/script/mesh_polyfill.js) in headless Chromium,
# for two whole images converted to the default SVG: fruits --segment (~24,000 patches) and
# fruits --segment --max-error 6 (~16,000 patches). Each is opened with
# window.gradmeshMeshOptions = {timing: true}, so that the script prints the time it took to
# find, parse, tessellate, draw and paint every mesh; read from Chromium's log. Runs RUNS times
# each (at least 5 for the medians printed).
# Usage: bash bench/browser_draw.sh [RUNS]   (outputs under bench-out/browser/)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
gm=build/app/gradmesh
out=bench-out/browser
mkdir -p "$out"
echo "script: $(wc -c < build/formats/svg/generated/mesh_polyfill.min.js) bytes minified"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"

# The median of the numbers on standard input, one a line.
median() { sort -g | awk '{v[NR] = $1} END {print NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

bench_image() {  # NAME, then the convert options
  local name=$1; shift
  [ -f "$out/$name.gmb" ] || $gm convert samples/fruits.jpg "$@" -o "$out/$name.gmb" >/dev/null
  $gm convert "$out/$name.gmb" -o "$out/$name.svg"
  echo "== $name (fruits.jpg $*): $($gm info "$out/$name.gmb" | grep -E '^patches:')"
  for mode in default; do
    local options='{timing:true}'
    # The options go in a script before the meshes, right after the root element's start tag.
    python3 - "$out/$name.svg" "$out/${name}_$mode.svg" "$options" <<'PY'
import sys
svg = open(sys.argv[1]).read()
at = svg.index('>', svg.index('<svg ')) + 1
open(sys.argv[2], 'w').write(svg[:at] + '<script>window.gradmeshMeshOptions=' + sys.argv[3] +
                             '</script>' + svg[at:])
PY
    local times=()
    for run in $(seq "$runs"); do
      rm -rf "$out/profile"
      local line
      line=$(chromium --headless --no-sandbox --disable-gpu-sandbox --use-angle=swiftshader \
        --enable-unsafe-swiftshader --hide-scrollbars --force-device-scale-factor=1 --no-first-run \
        --disable-extensions --user-data-dir="$PWD/$out/profile" --enable-logging=stderr --v=0 \
        --virtual-time-budget=60000 --window-size=512,480 --screenshot="$PWD/$out/${name}_$mode.png" \
        "file://$PWD/$out/${name}_$mode.svg" 2>&1 | grep -o '"gradmesh [^"]*"' | head -1 || true)
      times+=("$(echo "$line" | awk '{print $4}')")
    done
    printf '%-8s median %6.0f ms over %d runs (%s ms)\n' "$mode" \
      "$(printf '%s\n' "${times[@]}" | median)" "$runs" "$(printf '%.0f ' "${times[@]}")"
  done
}

bench_image fruits --segment
bench_image fruits_16k --segment --max-error 6
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
