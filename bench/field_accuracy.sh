#!/usr/bin/env bash
# Issue 56 item 2: the guiding field's accuracy inside media (tools/field_accuracy.cpp) on the talk's
# four situations: densesphere (dense, lit from behind), backlit (dense slab), thin, sss, and aniso. Each
# scene's field is trained once with guided_volpath's defaults at seed 1 and saved (FIELD_XML, if set,
# adds parameters to the training integrator: e.g. a candidate fix), then probed along one line into
# the medium. Writes WORK_DIR/<scene>.csv; python/examples/plot_field_accuracy.py plots them.
#   bench/field_accuracy.sh [BUILD_DIR] [WORK_DIR]
# Environment: SCENES, SPP (512), DIRS (64), INSCATTER_DIRS (32), FIELD_XML.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build}
WORK=${2:-$ROOT/bench/results/field-accuracy}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)  # absolute: the integrator files are included from the scenes

line() {  # scene -> the probe line's options: from the camera's or the light's side into the medium
    case $1 in
        densesphere) echo "--from 0,0,5 --dir 0,0,-1 --depths 0.25,0.5,1,2,3,4,6,8,10,12,14,15.5" ;;
        backlit) echo "--from 0,0,5 --dir 0,0,-1 --depths 0.1,0.25,0.5,0.75,1,1.25,1.5,2,2.5,3" ;;
        thin) echo "--from 5,0.3,0 --dir -1,0,0 --depths 0.05,0.1,0.2,0.3,0.4,0.5,0.6,0.8,1,1.15" ;;
        sss) echo "--from 0.3,5,0 --dir 0,-1,0 --depths 0.25,0.5,1,2,4,8,16,32,64,100" ;;
        aniso) echo "--from -5,0.3,0 --dir 1,0,0 --depths 0.25,0.5,1,2,3,4,6,8,10,12" ;;
        *) echo "no probe line for $1" >&2; exit 2 ;;
    esac
}

for sc in ${SCENES:-densesphere backlit thin sss aniso}; do
    field="$WORK/$sc.field"
    if [ ! -f "$field" ]; then
        printf '<?xml version="1.0" encoding="utf-8"?>\n<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/><string name="save_field" value="%s"/>%s</integrator></scene>\n' \
            "$field" "${FIELD_XML:-}" > "$WORK/train_$sc.xml"
        "$BUILD/volguide" render "$ROOT/bench/scenes/$sc.xml" -D width=160 -D height=120 \
            -D integrator_xml="$WORK/train_$sc.xml" --spp 1 --seed 1 -o "$WORK/train_$sc.exr" --quiet >/dev/null
    fi
    # shellcheck disable=SC2046
    "$BUILD/field_accuracy" "$ROOT/bench/scenes/$sc.xml" "$field" $(line "$sc") --scene-name "$sc" \
        --spp "${SPP:-512}" --dirs "${DIRS:-64}" --inscatter-dirs "${INSCATTER_DIRS:-32}" --out "$WORK/$sc.csv"
done
