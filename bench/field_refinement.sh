#!/usr/bin/env bash
# The transport-shaped refinement (issue 22, `leaf_contrast`): the guiding field's in-scattered
# estimate (80x60, photon training, default leaf_samples) against a path-traced volume-only
# reference (4096 spp, seed 77), for each leaf_contrast x leaf_contrast_samples, with the field's
# leaf counts. docs/guiding-estimates.md has the table.
#   bench/field_refinement.sh SCENE [BUILD_DIR] [WORK_DIR]   (CONTRASTS, SAMPLES: space-separated)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SCENE_NAME=${1:?usage: field_refinement.sh SCENE [BUILD_DIR] [WORK_DIR]}
BUILD=${2:-$ROOT/build}
WORK=${3:-$ROOT/bench/results/field-refinement}
CONTRASTS=${CONTRASTS:-0 0.1 0.2 0.3}
SAMPLES=${SAMPLES:-128 256 512}
mkdir -p "$WORK"
VG="$BUILD/volguide"
SCENE="$ROOT/bench/scenes/$SCENE_NAME.xml"
SIZE=(-D width=80 -D height=60)

source "$ROOT/bench/field_common.sh"
ref="$WORK/$SCENE_NAME-reference.exr"
reference "$SCENE" "$ref"

printf '| scene | leaf_contrast | leaf_contrast_samples | leaves (valid) | preprocess (s) | relMSE (eps 1e-2) | relMSE (eps 1e-3) | mean ratio |\n|---|---:|---:|---:|---:|---:|---:|---:|\n'
for c in $CONTRASTS; do
  for n in $SAMPLES; do
    [ "$c" = 0 ] && [ "$n" != "${SAMPLES%% *}" ] && continue  # off: the sample floor does not matter
    name="$SCENE_NAME-c$c-n$n"
    integrator "$name" "    <integrator type=\"guided_volpath\">
        <integer name=\"max_depth\" value=\"\$max_depth\"/>
        <integer name=\"photons\" value=\"50000000\"/>
        <float name=\"leaf_contrast\" value=\"$c\"/>
        <integer name=\"leaf_contrast_samples\" value=\"$n\"/>
        <string name=\"estimate\" value=\"inscattered\"/>
    </integrator>"
    "$VG" render "$SCENE" "${SIZE[@]}" -D integrator_xml="$WORK/$name.xml" --spp 16 --seed 3 \
        -o "$WORK/$name.exr" --stats "$WORK/$name.json" --quiet >/dev/null 2>&1
    "$VG" diff "$WORK/$name.exr" "$ref" --min-reference 1e-4 --json > "$WORK/$name.diff.json"
    /usr/bin/python3 - "$WORK/$name.json" "$WORK/$name.diff.json" "$SCENE_NAME" "$c" "$n" <<'PY'
import json, sys
st = json.load(open(sys.argv[1]))
d = json.load(open(sys.argv[2]))
i = st["integrator"]
print(f"| {sys.argv[3]} | {sys.argv[4]} | {sys.argv[5]} | {int(i['field_leaves'])} ({int(i['field_valid_leaves'])}) | "
      f"{st['time']['preprocess']:.2f} | {d['relmse_1e-2']:.3g} | {d['relmse_1e-3']:.3g} | {d['ratio']:.3f} |")
PY
  done
done
