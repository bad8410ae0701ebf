# Sourced by bench/field_estimates.sh (WORK, VG and SIZE set by the
# caller): integrator files and the volume-only volpath reference the field estimates are scored on.

integrator() {  # name body: writes $WORK/name.xml holding the integrator element `body`
    printf '<?xml version="1.0" encoding="utf-8"?>\n<scene version="3.0.0">\n%s\n</scene>\n' "$2" > "$WORK/$1.xml"
}

reference() {  # scene.xml out.exr: volpath volume_only, 4096 spp, seed 77 (rendered once, then kept)
    integrator reference '    <integrator type="volpath">
        <integer name="max_depth" value="$max_depth"/>
        <boolean name="volume_only" value="true"/>
    </integrator>'
    if [ ! -f "$2" ]; then
        "$VG" render "$1" "${SIZE[@]}" -D integrator_xml="$WORK/reference.xml" --spp 4096 --seed 77 \
            -o "$2" --quiet >/dev/null
    fi
}
