#!/usr/bin/env bash
# Configures the fuzz build (clang, ASan + UBSan + libFuzzer's coverage instrumentation over all of
# volguide; docs/reliability.md) in BUILD_DIR when it has no build yet:
#   scripts/configure-fuzz.sh [BUILD_DIR]
# Used by scripts/fuzz.sh (the libFuzzer targets) and scripts/test-sanitize.sh (SANITIZE_ASAN_BUILD=fuzz:
# the unit and stat tests against the same instrumented library, CI's ASan + UBSan stage). The tests are
# configured, not built: a target builds only when asked for. No benchmarks, Python module or Open PGL.
set -euo pipefail
build=${1:-build-fuzz}
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ ! -f $build/CMakeCache.txt ]]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVOLGUIDE_FUZZ=ON \
    -DVOLGUIDE_BUILD_TESTS=ON -DVOLGUIDE_BUILD_BENCH=OFF -DVOLGUIDE_BUILD_PYTHON=OFF \
    -DVOLGUIDE_WITH_OPENPGL=OFF
fi
