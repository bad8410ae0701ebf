#!/usr/bin/env bash
# `make demo`: renders the bundled demo scene once, to out/demo.exr and an sRGB preview out/demo.png.
set -euo pipefail
build_dir=${1:-build}
mkdir -p out
"$build_dir/volguide" render scenes/demo/cornell-box.xml -o out/demo.exr -o out/demo.png --stats out/demo-stats.json
