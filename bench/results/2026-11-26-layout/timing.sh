#!/bin/bash
# interleaved whole-render timings, base vs main, guided defaults (loaded field) and volpath
cd /work/main
for scene in shafts cloud fogbox sss; do
  f=/work/idbase/fields/$scene.field
  cat > /tmp/tm-$scene.xml <<X
<?xml version="1.0" encoding="utf-8"?>
<scene version="3.0.0">
    <integrator type="guided_volpath">
        <integer name="max_depth" value="\$max_depth"/>
        <string name="load_field" value="$f"/>
    </integrator>
</scene>
X
  for rep in 1 2 3; do
    for b in base main; do
      g=$(/work/$b/build/volguide render bench/scenes/$scene.xml -o /tmp/tm.exr -D width=160 -D height=120 --spp 16 --seed 3 --threads 2 -D integrator_xml=/tmp/tm-$scene.xml 2>&1 | sed -n 's/.*render \([0-9.]*\) s).*/\1/p')
      v=$(/work/$b/build/volguide render bench/scenes/$scene.xml -o /tmp/tm.exr -D width=160 -D height=120 --spp 16 --seed 3 --threads 2 2>&1 | sed -n 's/.*render \([0-9.]*\) s).*/\1/p')
      echo "$scene $b guided $g volpath $v"
    done
  done
done
