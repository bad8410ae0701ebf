#!/bin/bash
# Issue 21's fixed-sample-count comparison of learned selection on saved fields: the full system
# with selection_spp=0 (no selection) and with its default (a 2-spp pilot), plus optional extra
# variants as XML. Prints the render seconds (plus the pilot's), relMSE (eps 1e-2) against
# bench/references/, efficiency 1 / (relMSE x seconds) and the learned shares.
#   scripts/selection_variants.sh BUILD_DIR FIELD_DIR "shafts:64 thin:512 fogbox:128 backlit:256"
# A missing FIELD_DIR/<scene>.field is trained first (photons 50000000, as the benchmark asks).
# SEED (environment, default 1): the renders' seed.
set -euo pipefail
B=$1 F=$2
cd "$(dirname "$0")/.."
mkdir -p "$F"
for ss in $3; do
  sc=${ss%%:*} spp=${ss##*:}
  if [ ! -f "$F/$sc.field" ]; then
    printf '<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/><integer name="photons" value="50000000"/><integer name="selection_spp" value="0"/><string name="save_field" value="%s"/></integrator></scene>\n' "$F/$sc.field" > "$F/train_$sc.xml"
    "$B/volguide" render "bench/scenes/$sc.xml" -o "$F/train_$sc.exr" --spp 1 --quiet -D integrator=guided_volpath -D "integrator_xml=$F/train_$sc.xml" > /dev/null
  fi
  for v in 0 2; do
    printf '<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/><string name="load_field" value="%s"/><integer name="selection_spp" value="%s"/></integrator></scene>\n' "$F/$sc.field" "$v" > "$F/sel_${sc}_$v.xml"
    "$B/volguide" render "bench/scenes/$sc.xml" -o "$F/out.exr" --spp "$spp" --seed "${SEED:-1}" --quiet -D integrator=guided_volpath \
      -D "integrator_xml=$F/sel_${sc}_$v.xml" --reference "bench/references/$sc.exr" --stats "$F/stats.json" > /dev/null
    /usr/bin/python3 - "$F/stats.json" "$sc" "$v" "$spp" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); i = d["integrator"]
t = d["time"]["render"] + i.get("selection_seconds", 0.0)
r = d["reference"]["relmse_1e-2"]
shares = " ".join(f"{k[10:-11]}={i[k]:.2f}" for k in sorted(i) if k.endswith("_mean_share"))
print(f"{sys.argv[2]} selection_spp={sys.argv[3]} spp={sys.argv[4]} time {t:6.2f}s relMSE {r:.4g} "
      f"eff {1 / (r * t):.4g} {shares}", flush=True)
PY
  done
done
