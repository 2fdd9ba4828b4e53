#!/usr/bin/env bash
# Installs what is missing, builds (Release), and runs the main job on a bundled sample:
# the outputs land in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
gm=build/app/gradmesh
set -x
# The main job: a photographed object with its mask -> gradient mesh, in every output format.
$gm convert samples/apple.jpg --mask samples/apple_mask.png -o out/apple.gmb --report out/apple.json
$gm info out/apple.gmb
$gm convert out/apple.gmb -o out/apple-compact.gmb --compact
# The SVG: one meshgradient patch per mesh patch, colours by SVG's bicubic rule as Inkscape
# draws them (the mesh is fitted in that model), editable; .svgz is the same, gzipped.
$gm convert out/apple.gmb -o out/apple.svg
$gm convert out/apple.gmb -o out/apple.svgz
# Free colour slopes (--colors hermite): the smallest raster error per patch; its SVG is refitted
# to the bicubic rule (the error is printed), or subdivided with --svg-colors exact.
$gm convert samples/apple.jpg --mask samples/apple_mask.png --colors hermite -o out/apple-hermite.gmb
$gm convert out/apple-hermite.gmb -o out/apple-hermite.svg
$gm convert out/apple.gmb -o out/apple.eps
$gm convert out/apple.gmb -o out/apple.pdf
$gm render out/apple.gmb -o out/apple.png --background white
$gm render out/apple.gmb -o out/apple-mesh.png --scale 2 --background white --mesh-lines '#2040ff'   # the mesh's grid
$gm compare samples/apple.jpg out/apple.png --mask samples/apple_mask.png
# A page to look at it (open in a browser): image, render, mesh lines, error heat map, zoom, figures.
$gm view out/apple.gmb --image samples/apple.jpg -o out/apple.html
# An object with holes: one mesh per region, one slit per hole; --legacy writes hole-free pieces.
$gm convert samples/pic1.png -o out/pic1.gmb --report out/pic1.json
$gm info out/pic1.gmb
$gm convert out/pic1.gmb -o out/pic1.svg
$gm convert out/pic1.gmb -o out/pic1-legacy.pdf --legacy
$gm render out/pic1.gmb -o out/pic1.png --background white
$gm render out/pic1.gmb -o out/pic1-mesh.png --scale 2 --background white --mesh-lines '#ff2080'
# A whole image: segmented into large regions, one mesh each (holes included) over a base mesh.
$gm convert samples/fruits.jpg --segment -o out/fruits.gmb --report out/fruits.json
$gm convert out/fruits.gmb -o out/fruits.svg
$gm render out/fruits.gmb -o out/fruits.png
$gm compare samples/fruits.jpg out/fruits.png
$gm view out/fruits.gmb --image samples/fruits.jpg -o out/fruits.html
# A cartoon: its ink outlines become flat shapes drawn over the regions' meshes.
$gm convert samples/HappyFish.jpg --segment -o out/fish.svg
$gm render out/fish.svg -o out/fish.png --background white
# A whole image at about 1 KB: 50 patches shared out over the regions, compact level 6 (its
# colours refitted to the file's grids).
$gm convert samples/HappyFish.jpg --segment --max-error 2 --total-patches 50 --compact-level 6 -o out/fish-1k.gmb
$gm render out/fish-1k.gmb -o out/fish-1k.png
$gm compare samples/HappyFish.jpg out/fish-1k.png
set +x
ls -l out
