#!/bin/bash
# Issue 20's fixed-sample-count comparison of the full system's distance variants on saved fields:
# full (defaults), full + distance_merge 0.5, full without distance guiding, and (issue 37) full with
# distance="vsp" (one decision per segment). Prints render seconds,
# relMSE (eps 1e-2, and trimmed) against bench/references/, efficiency 1 / (relMSE x seconds) and
# the mean bins per distance decision.
#   scripts/distance_variants.sh BUILD_DIR FIELD_DIR "shafts:128 fogbox:128 thin:512 backlit:256"
# A missing FIELD_DIR/<scene>.field is trained first (photons 50000000, as the benchmark asks).
# SEED (environment, default 1): the renders' seed. VARIANTS (default "full merge nodist"): which of
# full, merge, nodist, vsp to render. PHOTONS (default 50000000): the training's photons.
set -euo pipefail
B=$1 F=$2
cd "$(dirname "$0")/.."
mkdir -p "$F"
for ss in $3; do
  sc=${ss%%:*} spp=${ss##*:}
  if [ ! -f "$F/$sc.field" ]; then
    printf '<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/><integer name="photons" value="%s"/><string name="save_field" value="%s"/></integrator></scene>\n' "${PHOTONS:-50000000}" "$F/$sc.field" > "$F/train_$sc.xml"
    "$B/volguide" render "bench/scenes/$sc.xml" -o "$F/train_$sc.exr" --spp 1 --quiet -D integrator=guided_volpath -D "integrator_xml=$F/train_$sc.xml" > /dev/null
  fi
  for v in ${VARIANTS:-full merge nodist}; do
    extra=""
    [ $v = merge ] && extra='<float name="distance_merge" value="0.5"/>'
    [ $v = nodist ] && extra='<string name="distance" value="standard"/>'
    [ $v = vsp ] && extra='<string name="distance" value="vsp"/>'
    printf '<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/><string name="load_field" value="%s"/>%s</integrator></scene>\n' "$F/$sc.field" "$extra" > "$F/v_${sc}_$v.xml"
    "$B/volguide" render "bench/scenes/$sc.xml" -o "$F/out.exr" --spp "$spp" --seed "${SEED:-1}" --quiet -D integrator=guided_volpath \
      -D "integrator_xml=$F/v_${sc}_$v.xml" --reference "bench/references/$sc.exr" --stats "$F/stats.json" > /dev/null
    /usr/bin/python3 - "$F/stats.json" "$sc" "$v" "$spp" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); i = d["integrator"]; t = d["time"]["render"]
r, rt = d["reference"]["relmse_1e-2"], d["reference"]["relmse_1e-2_trimmed"]
print(f"{sys.argv[2]} {sys.argv[3]:6s} spp={sys.argv[4]} render {t:6.2f}s relMSE {r:.4g} trimmed {rt:.4g} "
      f"eff {1 / (r * t):.4g} bins/query {i.get('distance_average_steps', 0):.2f}", flush=True)
PY
  done
done
