#!/usr/bin/env bash
# `make demo`: renders the bundled demo scene to out/demo.exr and out/demo.png.
set -euo pipefail
build_dir=${1:-build}
mkdir -p out
"$build_dir/volguide" render scenes/demo/cornell-box.xml -o out/demo.exr --stats out/demo-stats.json
"$build_dir/volguide" render scenes/demo/cornell-box.xml -o out/demo.png --quiet --spp 1 >/dev/null 2>&1 || true
