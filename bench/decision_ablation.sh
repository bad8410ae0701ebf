#!/usr/bin/env bash
# Issue 56 item 1: per-decision ablation at a fixed sample count with the training fixed. One field per
# scene is trained with guided_volpath's defaults and saved (save_field); every guided variant loads it
# (load_field), so the variants differ only in the decisions they make:
#   volpath     volpath, rr_rule=bounded (the baseline)
#   distance    distance=incremental direction=phase   (surface_guiding off)
#   direction   distance=standard    direction=product
#   both        distance=incremental direction=product
#   none        distance=standard    direction=phase (surface_guiding off): guided_volpath deciding nothing
# all guided ones with rrs=standard rr_rule=bounded allocation=false (no guided RR/splitting, no learned
# allocation). relMSE (eps 1e-2) against bench/references/<scene>.exr at 160x120 (the references' size).
#   bench/decision_ablation.sh [BUILD_DIR] [WORK_DIR]
# Environment: SCENES (default "densesphere backlit thin sss aniso shafts cloud"), SPP (64), SEEDS
# ("1 2 3 4"), VARIANTS ("volpath distance direction both"), EXTRA (XML added to every guided
# variant's integrator, e.g. a candidate fix's parameter), TRAIN_XML (XML added to the training
# integrator, e.g. leaf_samples), TAG (the CSV's variant name instead of the variant's). Appends CSV rows to WORK_DIR/ablation.csv
# (scene,variant,seed,spp,relmse,render_seconds); bench/ablation_summary.py turns them into the table.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build}
WORK=${2:-$ROOT/bench/results/decision-ablation}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)  # absolute: the integrator files are included from the scenes
VG="$BUILD/volguide"
SIZE=(-D width=160 -D height=120)
CSV="$WORK/ablation.csv"
[ -f "$CSV" ] || echo "scene,variant,seed,spp,relmse,render_seconds" > "$CSV"

xml() {  # file body
    printf '<?xml version="1.0" encoding="utf-8"?>\n<scene version="3.0.0">\n%s\n</scene>\n' "$2" > "$1"
}

train() {  # scene: the saved field (trained once, seed 1, guided_volpath's default training)
    local field="$WORK/$1.field"
    [ -f "$field" ] && return
    xml "$WORK/train_$1.xml" "<integrator type=\"guided_volpath\"><integer name=\"max_depth\" value=\"\$max_depth\"/>
        <string name=\"save_field\" value=\"$field\"/>${TRAIN_XML:-}</integrator>"
    "$VG" render "$ROOT/bench/scenes/$1.xml" "${SIZE[@]}" -D integrator_xml="$WORK/train_$1.xml" --spp 1 \
        --seed 1 -o "$WORK/train_$1.exr" --quiet >/dev/null
}

variant_xml() {  # scene variant -> prints the integrator file
    local f="$WORK/v_$1_$2.xml" d
    case $2 in
        volpath) xml "$f" '<integrator type="volpath"><integer name="max_depth" value="$max_depth"/>
        <string name="rr_rule" value="bounded"/></integrator>'; echo "$f"; return ;;
        distance) d='<string name="distance" value="incremental"/><string name="direction" value="phase"/>
        <boolean name="surface_guiding" value="false"/>' ;;
        direction) d='<string name="distance" value="standard"/><string name="direction" value="product"/>' ;;
        none) d='<string name="distance" value="standard"/><string name="direction" value="phase"/>
        <boolean name="surface_guiding" value="false"/>' ;;
        both) d='<string name="distance" value="incremental"/><string name="direction" value="product"/>' ;;
        *) echo "unknown variant $2" >&2; exit 2 ;;
    esac
    xml "$f" "<integrator type=\"guided_volpath\"><integer name=\"max_depth\" value=\"\$max_depth\"/>
        <string name=\"load_field\" value=\"$WORK/$1.field\"/><string name=\"rrs\" value=\"standard\"/>
        <string name=\"rr_rule\" value=\"bounded\"/><boolean name=\"allocation\" value=\"false\"/>
        $d ${EXTRA:-}</integrator>"
    echo "$f"
}

for sc in ${SCENES:-densesphere backlit thin sss aniso shafts cloud}; do
    train "$sc"
    for v in ${VARIANTS:-volpath distance direction both}; do
        f=$(variant_xml "$sc" "$v")
        for seed in ${SEEDS:-1 2 3 4}; do
            "$VG" render "$ROOT/bench/scenes/$sc.xml" "${SIZE[@]}" -D integrator_xml="$f" --spp "${SPP:-64}" \
                --seed "$seed" -o "$WORK/out.exr" --quiet --reference "$ROOT/bench/references/$sc.exr" \
                --stats "$WORK/stats.json" >/dev/null
            /usr/bin/python3 - "$WORK/stats.json" "$sc" "${TAG:-$v}" "$seed" "${SPP:-64}" >> "$CSV" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{sys.argv[5]},{d['reference']['relmse_1e-2']:.6g},{d['time']['render']:.3f}")
PY
            tail -1 "$CSV"
        done
    done
done
