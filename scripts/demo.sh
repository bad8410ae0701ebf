#!/usr/bin/env bash
# `make demo`: renders the bundled volumetric demo (fog lit by the sun through a window) twice for
# the same wall-clock time (DEMO_TIME seconds each, default 30, training included): with volpath and
# with guided_volpath's full system (its defaults: guided distances and product directions, guided
# Russian roulette and splitting), to out/demo-volpath.{exr,png} and out/demo.{exr,png} (guided),
# and prints each image's relMSE against the bundled reference scenes/demo/light-shafts-ref.exr
# (how it was made: scenes/demo/README.md).
set -euo pipefail
build_dir=${1:-build}
budget=${DEMO_TIME:-30}
reference=scenes/demo/light-shafts-ref.exr
mkdir -p out
declare -A relmse spp
for method in volpath guided_volpath; do
    stem=out/demo
    [ "$method" = volpath ] && stem=out/demo-volpath
    echo "demo: $method for ${budget} s ..."
    log=$("$build_dir/volguide" render scenes/demo/light-shafts.xml -D integrator=$method --time "$budget" \
        -o "$stem.exr" -o "$stem.png" --stats "$stem-stats.json" --reference "$reference" --quiet)
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
