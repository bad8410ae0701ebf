#!/usr/bin/env bash
# Bit-identity check for refactors (issue 18's acceptance): renders every benchmark scene at 64x48,
# 8 spp, fixed seed, with volpath and with guided_volpath (the defaults, each guided decision alone,
# distance=vsp, rrs=ears), every guided render from a field saved once per scene, plus the defaults
# trained from scratch (the photon pre-pass, the pixel estimate and the learned selection included).
#
#   scripts/identity_check.sh render BUILD_DIR OUT_DIR [FIELDS_DIR]
#       renders every case into OUT_DIR/<scene>__<case>.exr; without FIELDS_DIR it first trains and
#       saves one field per scene into OUT_DIR/fields/ (100 k photons, seed 7), with FIELDS_DIR it
#       loads the fields saved there (so that a new build renders from the parent's fields).
#   scripts/identity_check.sh compare DIR_A DIR_B BUILD_DIR
#       compares the images pixel for pixel (the same bytes, or `volguide diff` MSE exactly 0)
#       and prints one line per case; exit 1 if any differs.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
scenes=(shafts sss cloud fogbox thin aniso backlit densesphere glassfog)
# case name -> guided_volpath parameters (empty: volpath)
declare -A cases=(
  [volpath]=""
  [defaults]="distance=incremental direction=product rrs=grrs"
  [distance]="distance=incremental direction=phase rrs=standard"
  [direction]="distance=standard direction=product rrs=standard"
  [incident]="distance=standard direction=incident rrs=standard"
  [grrs]="distance=standard direction=phase rrs=grrs"
  [grr]="distance=incremental direction=product rrs=grr"
  # issue 37/38's decisions (the per-vertex object: vsp's P_G, ears' leaf, the pilot's records)
  [vsp]="distance=vsp direction=product rrs=grrs"
  [vspphase]="distance=vsp direction=phase rrs=standard"
  [ears]="distance=incremental direction=product rrs=ears"
  # the defaults with nothing given, trained here (not from the saved field)
  [trained]="photons=100000"
)

integrator_xml() {  # $1 = file, $2.. = name=value
  local f="$1"; shift
  {
    echo '<?xml version="1.0" encoding="utf-8"?>'
    echo '<scene version="3.0.0">'
    echo '    <integrator type="guided_volpath">'
    echo '        <integer name="max_depth" value="$max_depth"/>'
    local kv name value kind
    for kv in "$@"; do
      name="${kv%%=*}"; value="${kv#*=}"
      if [[ "$value" =~ ^-?[0-9]+$ ]]; then kind=integer
      elif [[ "$value" =~ ^-?[0-9]*\.[0-9]+$ ]]; then kind=float
      elif [[ "$value" == true || "$value" == false ]]; then kind=boolean
      else kind=string; fi
      echo "        <$kind name=\"$name\" value=\"$value\"/>"
    done
    echo '    </integrator>'
    echo '</scene>'
  } > "$f"
}

render_one() {  # build out scene case xml
  local build="$1" out="$2" scene="$3" name="$4" xml="$5"
  local args=(-D width=64 -D height=48 --spp 8 --seed 7 --threads 2 --quiet)
  [[ -n "$xml" ]] && args+=(-D "integrator_xml=$xml")
  "$build/volguide" render "$here/bench/scenes/$scene.xml" -o "$out/${scene}__${name}.exr" "${args[@]}"
}

cmd="${1:-}"
case "$cmd" in
  render)
    build="$(cd "$2" && pwd)"; mkdir -p "$3"; out="$(cd "$3" && pwd)"
    fields="${4:-}"
    xmls="$out/xml"; mkdir -p "$xmls"
    if [[ -z "$fields" ]]; then
      fields="$out/fields"; mkdir -p "$fields"
      for scene in "${scenes[@]}"; do
        integrator_xml "$xmls/train-$scene.xml" photons=100000 "save_field=$fields/$scene.field"
        render_one "$build" "$out" "$scene" train "$xmls/train-$scene.xml"
        rm -f "$out/${scene}__train.exr"
      done
    else
      fields="$(cd "$fields" && pwd)"
    fi
    for scene in "${scenes[@]}"; do
      for name in "${!cases[@]}"; do
        if [[ "$name" == volpath ]]; then
          render_one "$build" "$out" "$scene" "$name" ""
        elif [[ "$name" == trained ]]; then
          # shellcheck disable=SC2086
          integrator_xml "$xmls/$scene-$name.xml" ${cases[$name]}
          render_one "$build" "$out" "$scene" "$name" "$xmls/$scene-$name.xml"
        else
          # shellcheck disable=SC2086
          integrator_xml "$xmls/$scene-$name.xml" "load_field=$fields/$scene.field" ${cases[$name]}
          render_one "$build" "$out" "$scene" "$name" "$xmls/$scene-$name.xml"
        fi
      done
    done
    ;;
  compare)
    a="$2"; b="$3"; build="$4"; status=0
    for scene in "${scenes[@]}"; do
      for name in $(printf '%s\n' "${!cases[@]}" | sort); do
        f="${scene}__${name}.exr"
        if cmp -s "$a/$f" "$b/$f"; then echo "identical  $f"; continue; fi
        line=$("$build/volguide" diff "$a/$f" "$b/$f" --json)
        # MSE in double of float differences: 0 only when every pixel channel is equal.
        if python3 -c 'import json,sys; d=json.loads(sys.argv[1]); sys.exit(0 if d["mse"]==0 and d["nonfinite"]==0 else 1)' "$line"; then
          echo "identical  $f"
        else
          echo "DIFFERENT  $f  $line"; status=1
        fi
      done
    done
    exit $status
    ;;
  *) sed -n '2,13p' "$0"; exit 2 ;;
esac
