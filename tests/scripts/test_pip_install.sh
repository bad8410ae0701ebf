#!/usr/bin/env bash
# `pip install --no-build-isolation` of the source tree into a fresh venv (docs/python.md, "Installing
# with pip"), offline (--no-index: nothing downloaded; numpy from Debian's site packages), reusing the
# project's CMake build directory (VOLGUIDE_CMAKE_BUILD_DIR) so that it relinks nothing; then, from
# another directory, `import volguide` renders the fog box to numpy and the installed `volguide`
# command renders it to an EXR.
#   tests/scripts/test_pip_install.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$(realpath "$1")
build=$(realpath "$2")
python=/usr/bin/python3  # Debian's, whose numpy, setuptools and wheel packages the install uses
work=$(mktemp -d /tmp/volguide-pip.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
VOLGUIDE_CMAKE_BUILD_DIR="$build" VOLGUIDE_CMAKE_JOBS=2 \
    "$work/venv/bin/pip" install --no-build-isolation --no-index --quiet "$src"
cd "$work"
"$work/venv/bin/python" - "$src" "$work" <<'PY'
import sys
import numpy as np
import volguide
src, work = sys.argv[1], sys.argv[2]
assert volguide.__file__.startswith(work + "/venv/"), volguide.__file__
scene = volguide.load_scene(src + "/bench/scenes/fogbox.xml", width=16, height=12, spp=2)
image, stats = volguide.render(scene, spp=2, seed=1)
assert image.shape == (12, 16, 3) and image.dtype == np.float32, image.shape
assert np.isfinite(image).all() and image.mean() > 0, image.mean()
print("pip-installed module:", volguide.__file__, "image mean", float(image.mean()), "spp", stats["spp"])
PY
"$work/venv/bin/volguide" render "$src/bench/scenes/fogbox.xml" -D width=16 -D height=12 --spp 1 --quiet \
    -o "$work/cli.exr" | grep -q "^spp: 1$"
[[ -s "$work/cli.exr" ]]
echo "PASSED: pip install --no-build-isolation, import volguide and the volguide command from a venv"
