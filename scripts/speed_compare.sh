#!/usr/bin/env bash
# Speed of a build against another (a refactor's "speed unchanged within noise" check), measured in
# one run, alternating the two builds so that a drift of the shared machine hits both alike:
#   1. the whole-render micro-benchmarks (bench_render: BM_DemoRender; bench_volpath:
#      BM_LightShaftsVolpath, BM_CloudVolpath), each build `ROUNDS` times;
#   2. `volguide render` of bench/scenes/shafts.xml for SECONDS with volpath and with guided_volpath's
#      defaults (the full system), each build `ROUNDS` times: the spp reached (and render seconds).
#
#   scripts/speed_compare.sh OLD_BUILD NEW_BUILD OUT_DIR [SECONDS=20] [ROUNDS=2]
# Prints one table per part; the raw JSON stays in OUT_DIR. Run it on an otherwise idle machine.
set -euo pipefail
[ $# -ge 3 ] || { sed -n 2,9p "$0" >&2; exit 2; }
old="$1" new="$2" out="$3" seconds="${4:-20}" rounds="${5:-2}"
here="$(cd "$(dirname "$0")/.." && pwd)"
mkdir -p "$out"

micro() {  # $1 = build, $2 = tag
  "$1/bench_render" --benchmark_filter='BM_DemoRender' --benchmark_out="$out/render_$2.json" \
    --benchmark_out_format=json > /dev/null
  "$1/bench_volpath" --benchmark_filter='BM_(LightShafts|Cloud)Volpath' \
    --benchmark_out="$out/volpath_$2.json" --benchmark_out_format=json > /dev/null
}

shafts() {  # $1 = build, $2 = tag, $3 = integrator
  "$1/volguide" render "$here/bench/scenes/shafts.xml" -o "$out/shafts_$3_$2.exr" --time "$seconds" \
    --seed 1 -D "integrator=$3" --stats "$out/shafts_$3_$2.json" --quiet
}

for r in $(seq 1 "$rounds"); do
  for side in old new; do
    build=$old; [ $side = new ] && build=$new
    echo "round $r: $side micro-benchmarks" >&2
    micro "$build" "${side}_$r"
  done
done
for r in $(seq 1 "$rounds"); do
  for integrator in volpath guided_volpath; do
    for side in old new; do
      build=$old; [ $side = new ] && build=$new
      echo "round $r: $side shafts $integrator ${seconds}s" >&2
      shafts "$build" "${side}_$r" "$integrator"
    done
  done
done

python3 - "$out" "$rounds" <<'EOF'
import json, sys, statistics
out, rounds = sys.argv[1], int(sys.argv[2])
def times(kind, side):
    per = {}
    for r in range(1, rounds + 1):
        for b in json.load(open(f"{out}/{kind}_{side}_{r}.json"))["benchmarks"]:
            per.setdefault(b["name"], []).append(b["real_time"])
    return per
print("| benchmark | old ms | new ms | new/old |\n|---|---|---|---|")
for kind in ("render", "volpath"):
    o, n = times(kind, "old"), times(kind, "new")
    for name in o:
        mo, mn = statistics.median(o[name]), statistics.median(n[name])
        print(f"| {name} | {mo:.1f} | {mn:.1f} | {mn / mo:.3f} |")
print("\n| shafts, --time | old spp | new spp | new/old |\n|---|---|---|---|")
for integrator in ("volpath", "guided_volpath"):
    spp = {}
    for side in ("old", "new"):
        spp[side] = [json.load(open(f"{out}/shafts_{integrator}_{side}_{r}.json"))["spp"] for r in range(1, rounds + 1)]
    mo, mn = statistics.median(spp["old"]), statistics.median(spp["new"])
    print(f"| {integrator} | {spp['old']} | {spp['new']} | {mn / mo:.3f} |")
EOF
