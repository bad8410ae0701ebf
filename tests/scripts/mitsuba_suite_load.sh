#!/bin/sh
# Issue 40: tries to load every scene of Mitsuba 3's render test suite (outside participating_media)
# with the CLI and prints the first error of each. Usage: mitsuba_suite_load.sh VOLGUIDE [SUITE_DIR]
# A scene "loads" when `volguide render` at 1 spp on a 1/8 crop succeeds.
set -u
cli=${1:?usage: $0 path/to/volguide [suite dir]}
suite=${2:-$(dirname "$0")/../../../shared/mitsuba-data/tests/scenes}
out=$(mktemp -d)
ok=0; total=0
for scene in $(find "$suite" -name '*.xml' -not -path '*/participating_media/*' -not -path '*/fragments/*' | sort); do
    total=$((total + 1))
    name=${scene#"$suite"/}
    if err=$("$cli" render "$scene" -o "$out/img.exr" --spp 1 --quiet 2>&1 >/dev/null); then
        ok=$((ok + 1)); echo "LOADS  $name"
    else
        echo "FAILS  $name: $(printf '%s\n' "$err" | head -n 1)"
    fi
done
echo "$ok/$total scenes load"
rm -rf "$out"
