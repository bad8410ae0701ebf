#!/usr/bin/env bash
# Reproduces the training-cost table of docs/guiding-estimates.md: the guiding field's in-scattered
# estimate on `shafts` (80x60) for photon training, scored against a path-traced volume-only
# reference (4096 spp, seed 77). (The table's camera-path rows need a binary from before issue 48,
# which retired camera-path training.)
#   bench/field_estimates.sh [BUILD_DIR] [WORK_DIR]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build}
WORK=${2:-$ROOT/bench/results/field-estimates}
mkdir -p "$WORK"
VG="$BUILD/volguide"
SCENE="$ROOT/bench/scenes/shafts.xml"
SIZE=(-D width=80 -D height=60)

source "$ROOT/bench/field_common.sh"
reference "$SCENE" "$WORK/reference.exr"

printf '| training | preprocess (s) | relMSE (eps 1e-2) | relMSE (eps 1e-3) | mean ratio |\n|---|---:|---:|---:|---:|\n'
run() {  # name photons leaf_samples
    integrator "$1" "    <integrator type=\"guided_volpath\">
        <integer name=\"max_depth\" value=\"\$max_depth\"/>
        <integer name=\"photons\" value=\"$2\"/>
        <integer name=\"leaf_samples\" value=\"$3\"/>
        <string name=\"estimate\" value=\"inscattered\"/>
    </integrator>"
    "$VG" render "$SCENE" "${SIZE[@]}" -D integrator_xml="$WORK/$1.xml" --spp 16 --seed 3 \
        -o "$WORK/$1.exr" --stats "$WORK/$1.json" --quiet >/dev/null 2>&1
    "$VG" diff "$WORK/$1.exr" "$WORK/reference.exr" --min-reference 1e-4 --json > "$WORK/$1.diff.json"
    /usr/bin/python3 - "$WORK/$1.json" "$WORK/$1.diff.json" "$1" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["time"]["preprocess"]
d = json.load(open(sys.argv[2]))
print(f"| {sys.argv[3]} | {t:.2f} | {d['relmse_1e-2']:.3g} | {d['relmse_1e-3']:.3g} | {d['ratio']:.3f} |")
PY
}
for n in 5 10 20 50; do run "photons-${n}M" "${n}000000" 300; done
