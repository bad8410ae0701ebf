#!/usr/bin/env bash
# `make demo`: renders the bundled volumetric demo (fog lit by the sun through a window) once,
# to out/demo.exr and an sRGB preview out/demo.png (volpath until guiding lands).
set -euo pipefail
build_dir=${1:-build}
mkdir -p out
"$build_dir/volguide" render scenes/demo/light-shafts.xml -o out/demo.exr -o out/demo.png --stats out/demo-stats.json
