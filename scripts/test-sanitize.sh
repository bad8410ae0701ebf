#!/usr/bin/env bash
# make test-sanitize: the unit, stat and fast integration tests under AddressSanitizer +
# UndefinedBehaviorSanitizer, and the multi-threaded render tests (render loop, photon pass,
# determinism) under ThreadSanitizer, each in its own build directory (docs/reliability.md).
#   scripts/test-sanitize.sh [ASAN_BUILD_DIR] [TSAN_BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
asan=${1:-build-asan}
tsan=${2:-build-tsan}
jobs=${JOBS:-$(nproc)}
# No benchmarks, Python module or Open PGL: they add build time and no reader or render-loop code.
common=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DVOLGUIDE_BUILD_BENCH=OFF -DVOLGUIDE_BUILD_PYTHON=OFF
        -DVOLGUIDE_WITH_OPENPGL=OFF)
# Integration tests too slow for an instrumented build (2-20x slower) or not about volguide's code:
# whole benchmark scenes, the benchmark harness, the install test and the Slurm cluster.
slow='bench_harness|install_embed|slurm_array|BenchScene\.|GuidedVsVolpathScenes|MitsubaConformance'

[[ -f $asan/CMakeCache.txt ]] || cmake -S "$root" -B "$asan" "${common[@]}" -DVOLGUIDE_SANITIZE=address,undefined
cmake --build "$asan" -j "$jobs"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
ctest --test-dir "$asan" --output-on-failure -j "$jobs" -L 'unit|stat|integration' -E "$slow" --timeout 1500

tsan_tests=(test_render_loop test_photon_pass test_determinism)
[[ -f $tsan/CMakeCache.txt ]] || cmake -S "$root" -B "$tsan" "${common[@]}" -DVOLGUIDE_SANITIZE=thread
cmake --build "$tsan" -j "$jobs" --target volguide_cli replay_sample "${tsan_tests[@]}"
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
# The gtest suites of those three files (ctest names are Suite.Test).
ctest --test-dir "$tsan" --output-on-failure -j "$jobs" -R '^(RenderLoop|PhotonPass|GuidedVolPath|Determinism)\.' \
  --timeout 1500
