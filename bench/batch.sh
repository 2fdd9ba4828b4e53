#!/usr/bin/env bash
# `gradmesh batch` against a shell loop of `gradmesh convert` over the same images, and a batch
# killed with SIGKILL halfway then resumed (docs/batch.md).
#
#   bash bench/batch.sh [BUILD_DIR]        (default: build; the gradmesh binary must exist)
#
# Makes BENCH_BATCH_IMAGES images (default 200) in bench-out/batch/in: the samples in turn,
# each cropped at another place and size, resized to BENCH_BATCH_SIDE pixels square (default
# 80) with oiiotool. Converts them (BENCH_BATCH_OPTIONS, default --segment: every crop converts
# whole) to .gmb with batch (--jobs BENCH_BATCH_JOBS, default 2) and
# with the loop, each timed by /usr/bin/time; prints images/s, CPU utilisation (of the cores
# the jobs may use) and peak RSS (the largest process), then checks that both wrote the same
# bytes. Then starts batch afresh, kills it with SIGKILL once a third of the images are logged,
# and reruns it: no finished output may be lost, none may be partial, no temporary may remain.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
gm=$(realpath "$build/app/gradmesh")
n=${BENCH_BATCH_IMAGES:-200}
side=${BENCH_BATCH_SIDE:-80}
read -r -a options <<<"${BENCH_BATCH_OPTIONS:---segment}"
jobs=${BENCH_BATCH_JOBS:-2}
work=bench-out/batch
rm -rf "$work"
mkdir -p "$work/in" "$work/out-loop"

samples=(apple.jpg astronaut.png chelsea.png fruits.jpg HappyFish.jpg horse.png pic1.png plant.jpg)
echo "== making $n images of ${side}x$side in $work/in" >&2
# One oiiotool per sample: each crop is cut from a copy of the sample (--dup), written, popped.
for ((j = 0; j < ${#samples[@]}; j++)); do
  s=samples/${samples[j]}
  read -r w h < <(oiiotool --info "$s" | sed -E 's/.*: *([0-9]+) x *([0-9]+),.*/\1 \2/')
  small=$(( w < h ? w : h ))
  args=()
  for ((k = j; k < n; k += ${#samples[@]})); do
    size=$(( small * (50 + (k * 7) % 51) / 100 ))          # 50% to 100% of the shorter side
    x=$(( (w - size) * ((k * 13) % 10) / 9 ))
    y=$(( (h - size) * ((k * 17) % 10) / 9 ))
    args+=(--dup --cut "${size}x${size}+${x}+${y}" --resize "${side}x${side}"
           -o "$(printf '%s/in/img%03d.png' "$work" "$k")" --pop)
  done
  oiiotool "$s" "${args[@]}"
done

timed() {  # timed NAME COMMAND...: /usr/bin/time's figures into $work/NAME.time
  local name=$1
  shift
  /usr/bin/time -f '%e %U %S %M' -o "$work/$name.time" "$@" >/dev/null 2>&1 || true
}
report() {  # report NAME: images/s, CPU utilisation, peak RSS
  read -r e u s m < <(tail -n 1 "$work/$1.time")
  awk -v name="$1" -v n="$n" -v e="$e" -v u="$u" -v s="$s" -v m="$m" -v c="$jobs" 'BEGIN {
    printf "%-6s %6.1f s  %6.2f images/s  CPU %5.1f%% of %d cores  peak RSS %6.1f MB\n",
           name, e, n / e, 100 * (u + s) / e / c, c, m / 1024 }'
}

echo "== batch (--jobs $jobs)" >&2
timed batch "$gm" batch "$work/in" --output-dir "$work/out-batch" --jobs "$jobs" --log "$work/batch.jsonl" "${options[@]}"
echo "== shell loop of convert" >&2
timed loop bash -c 'for f in "$1"/in/*.png; do b=${f##*/}; "$2" convert "$f" -o "$1/out-loop/${b%.png}.gmb" "${@:3}" || true; done' \
  sh "$work" "$gm" "${options[@]}"

echo "images: $n of ${side}x$side (${options[*]}), machine load $(cut -d' ' -f1-3 /proc/loadavg)"
report batch
report loop
read -r eb _ < <(tail -n 1 "$work/batch.time")
read -r el _ < <(tail -n 1 "$work/loop.time")
awk -v b="$eb" -v l="$el" 'BEGIN { printf "batch / loop throughput: %.2fx\n", l / b }'
ok=$(grep -c '"status":"ok"' "$work/batch.jsonl" || true)
same=0
for f in "$work"/out-loop/*.gmb; do cmp -s "$f" "$work/out-batch/${f##*/}" && same=$((same + 1)); done
echo "batch converted $ok of $n; $same outputs byte-identical to convert's ($(ls "$work"/out-loop | wc -l) made by the loop)"

echo "== SIGKILL a third of the way, then resume" >&2
out=$work/out-kill
log=$out/gradmesh-batch.jsonl
"$gm" batch "$work/in" --output-dir "$out" --jobs "$jobs" "${options[@]}" >/dev/null 2>&1 &
pid=$!
while [ "$(cat "$log" 2>/dev/null | wc -l)" -lt $((n / 3)) ]; do sleep 0.2; done
kill -9 "$pid"
wait "$pid" 2>/dev/null || true
sleep 1
before=$(grep -c '"status":"ok"' "$log" || true)
partial=0
for f in "$out"/*.gmb; do cmp -s "$f" "$work/out-batch/${f##*/}" || partial=$((partial + 1)); done
temps=$(find "$out" -name '.*gradmesh-tmp-*' | wc -l)
echo "killed: $before images logged, $(ls "$out"/*.gmb | wc -l) outputs, $partial differing or partial, $temps temporaries left"
"$gm" batch "$work/in" --output-dir "$out" --jobs "$jobs" "${options[@]}" >/dev/null 2>&1 || true
skipped=$(tail -n +$((before + 1)) "$log" | grep -c '"status":"skipped"' || true)
redone=$(tail -n +$((before + 1)) "$log" | grep -c '"status":"ok"' || true)
same=0
for f in "$work"/out-batch/*.gmb; do cmp -s "$f" "$out/${f##*/}" && same=$((same + 1)); done
temps=$(find "$out" -name '.*gradmesh-tmp-*' | wc -l)
echo "resumed: $skipped skipped as done (of $before), $redone converted, $same of $ok outputs identical to the first batch's, $temps temporaries left"
