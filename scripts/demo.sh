#!/usr/bin/env bash
# `make demo`: renders the bundled volumetric demo (fog lit by the sun through a window) with volpath
# and with guided_volpath's full system (its defaults: guided distances and product directions,
# guided Russian roulette and splitting) at the same time, side by side, each for the same wall-clock
# time (DEMO_TIME seconds, default 15, training included) on half of the machine's threads (at least
# one each): an equal-time comparison that shows both images after DEMO_TIME seconds instead of
# twice that. Writes out/demo-volpath.{exr,png} and out/demo.{exr,png} (guided), and prints each
# image's relMSE against the bundled reference scenes/demo/light-shafts-ref.exr (how it was made:
# scenes/demo/README.md) and the gain.
set -euo pipefail
build_dir=${1:-build}
budget=${DEMO_TIME:-15}
threads=$(( $(nproc) / 2 ))
(( threads >= 1 )) || threads=1
reference=scenes/demo/light-shafts-ref.exr
mkdir -p out
stem_of() { if [ "$1" = volpath ]; then echo out/demo-volpath; else echo out/demo; fi; }
echo "demo: volpath and guided_volpath side by side for ${budget} s each, ${threads} thread(s) each ..."
pids=()
for method in volpath guided_volpath; do
    stem=$(stem_of "$method")
    "$build_dir/volguide" render scenes/demo/light-shafts.xml -D integrator=$method --time "$budget" \
        --threads "$threads" -o "$stem.exr" -o "$stem.png" --stats "$stem-stats.json" --reference "$reference" \
        --quiet >"$stem.log" &
    pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid"; done
declare -A relmse spp
for method in volpath guided_volpath; do
    log=$(cat "$(stem_of "$method").log")
    relmse[$method]=$(sed -n 's/^relMSE vs reference: \([^ ]*\) (eps 1e-2).*/\1/p' <<<"$log")
    spp[$method]=$(sed -n 's/^spp: \([0-9]*\).*/\1/p' <<<"$log")
done
printf '\n%-16s %8s %16s\n' method spp "relMSE (1e-2)"
for method in volpath guided_volpath; do
    printf '%-16s %8s %16s\n' "$method" "${spp[$method]}" "${relmse[$method]}"
done
awk -v a="${relmse[volpath]}" -v b="${relmse[guided_volpath]}" \
    'BEGIN { if (b > 0) printf "guided_volpath: %.2fx lower relMSE than volpath at equal time\n", a / b }'
echo "images: out/demo.png (guided), out/demo-volpath.png"
