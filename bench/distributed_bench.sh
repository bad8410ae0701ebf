#!/usr/bin/env bash
# Distributed rendering on one machine (issue 23, docs/distributed.md):
#  1. throughput of one process with all threads vs N chunk processes of one thread each, splitting
#     the same samples (`render --field F --samples`), on a benchmark media scene;
#  2. `volguide merge` time per megapixel (4 parts of a 1920x1080 frame).
#   bench/distributed_bench.sh [BUILD_DIR] [SPP] [WIDTH] [HEIGHT]
# Prints a Markdown table; the numbers in docs/distributed.md come from
# `bench/distributed_bench.sh build 32 320 240` on the development machine (2 cores, shared).
set -euo pipefail
build=$(realpath "${1:-build}")
spp=${2:-32}
width=${3:-320}
height=${4:-240}
cli=$build/volguide
repo=$(dirname "$(dirname "$(realpath "$0")")")
scene=$repo/bench/scenes/fogbox.xml
cores=$(nproc)
work=$(mktemp -d /tmp/volguide-distbench.XXXXXX)
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }
secs() { python3 -c "print(f'{$2 - $1:.3f}')"; }
defs=(-D integrator=guided_volpath -D width="$width" -D height="$height")

t0=$(now)
"$cli" train "$scene" "${defs[@]}" -o "$work/f.vgt" --seed 1 --quiet >/dev/null
t1=$(now)
train=$(secs "$t0" "$t1")

t0=$(now)
"$cli" render "$scene" "${defs[@]}" --field "$work/f.vgt" --seed 1 --samples "0:$spp" --threads "$cores" \
    -o "$work/one.exr" --quiet >/dev/null
t1=$(now)
one=$(secs "$t0" "$t1")

per=$(( spp / cores ))
t0=$(now)
pids=()
for ((i = 0; i < cores; ++i)); do
    "$cli" render "$scene" "${defs[@]}" --field "$work/f.vgt" --seed 1 --samples "$((i * per)):$per" --threads 1 \
        -o "$work/chunk-$i.exr" --quiet >/dev/null &
    pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid"; done
t1=$(now)
many=$(secs "$t0" "$t1")
"$cli" merge "$work"/chunk-*.exr -o "$work/merged.exr" >/dev/null
rel=$("$cli" diff "$work/merged.exr" "$work/one.exr" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['relmse_1e-2'])")

# Merge cost: 4 parts of a 1920x1080 frame (direct light only, 1 spp each: cheap to make).
mdefs=(-D integrator=volpath -D max_depth=1 -D width=1920 -D height=1080)
for i in 0 1 2 3; do
    "$cli" render "$scene" "${mdefs[@]}" --seed 1 --samples "$i:1" -o "$work/m-$i.exr" --quiet >/dev/null
done
t0=$(now)
"$cli" merge "$work"/m-?.exr -o "$work/m.exr" >/dev/null
t1=$(now)
merge=$(secs "$t0" "$t1")
mp=$(python3 -c "print(1920 * 1080 / 1e6)")

px=$(( width * height ))
python3 - "$train" "$one" "$many" "$spp" "$px" "$cores" "$merge" "$mp" "$rel" <<'PY'
import sys
train, one, many, spp, px, cores, merge, mp, rel = sys.argv[1:]
train, one, many, merge, mp, rel = map(float, (train, one, many, merge, mp, rel))
spp, px, cores = int(spp), int(px), int(cores)
print(f"| measurement | value |\n|---|---|")
print(f"| training (guided_volpath defaults, fogbox {px} px) | {train:.2f} s |")
print(f"| 1 process x {cores} threads, {spp} spp | {one:.2f} s wall, {spp * px / one / 1e6:.3f} Msamples/s |")
print(f"| {cores} processes x 1 thread, {spp // cores} spp each | {many:.2f} s wall, {spp * px / many / 1e6:.3f} Msamples/s |")
print(f"| chunked / single throughput | {one / many:.3f} |")
print(f"| merged chunks vs single process, relMSE(1e-2) | {rel:.3g} |")
print(f"| merge, 4 parts of 1920x1080 | {merge:.2f} s = {merge / (4 * mp):.3f} s per part-megapixel |")
PY
