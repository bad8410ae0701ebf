#!/usr/bin/env bash
# make test-sanitize: the unit, stat and fast integration tests under AddressSanitizer +
# UndefinedBehaviorSanitizer, and the multi-threaded render tests (render loop, photon pass,
# determinism) under ThreadSanitizer, each in its own build directory (docs/reliability.md; the ASan
# stage can instead use the fuzz build, SANITIZE_ASAN_BUILD below).
#   scripts/test-sanitize.sh [ASAN_BUILD_DIR] [TSAN_BUILD_DIR]
# SANITIZE_STAGES: "asan tsan" (default) or one of them; SANITIZE_LABELS: the CTest labels of the
# ASan + UBSan stage (default unit|stat|integration; CI runs a subset, see .ci/run).
# SANITIZE_ASAN_BUILD: gcc (default: the ASan + UBSan stage in its own gcc build, ASAN_BUILD_DIR) or
# fuzz: in the fuzz build (clang 14, ASan + UBSan and libFuzzer's coverage instrumentation,
# FUZZ_BUILD_DIR, default build-fuzz; scripts/configure-fuzz.sh), whose instrumented library make fuzz
# has already built: CI's stage (.ci/run), one instrumented build for both uses.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
asan=${1:-build-asan}
tsan=${2:-build-tsan}
jobs=${JOBS:-$(nproc)}
stages=${SANITIZE_STAGES:-asan tsan}
labels=${SANITIZE_LABELS:-unit|stat|integration}
asan_build=${SANITIZE_ASAN_BUILD:-gcc}
# No benchmarks, Python module or Open PGL: they add build time and no reader or render-loop code.
common=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DVOLGUIDE_BUILD_BENCH=OFF -DVOLGUIDE_BUILD_PYTHON=OFF
        -DVOLGUIDE_WITH_OPENPGL=OFF)
# Integration tests too slow for an instrumented build (2-20x slower) or not about volguide's code:
# whole benchmark scenes (AllScenes/BenchScene.*), the guided-vs-volpath scene comparisons, the
# Mitsuba conformance renders, the benchmark harness, the install test and the Slurm cluster.
slow='bench_harness|install_embed|slurm_array|BenchScene\.|GuidedVsVolpathScenes|MitsubaConformance'

if [[ " $stages " == *" asan "* ]]; then
  if [[ $asan_build == fuzz ]]; then
    asan=${FUZZ_BUILD_DIR:-build-fuzz}
    "$root/scripts/configure-fuzz.sh" "$asan"
    if ! grep -q '^VOLGUIDE_FUZZ:BOOL=ON' "$asan/CMakeCache.txt"; then
      echo "test-sanitize: $asan is not a fuzz build (VOLGUIDE_FUZZ=ON)" >&2
      exit 1
    fi
    # Its tests on (a fuzz build configured before they were, or with them off), its other settings kept.
    cmake -S "$root" -B "$asan" -DVOLGUIDE_BUILD_TESTS=ON > /dev/null
  elif [[ $asan_build == gcc ]]; then
    # Configured every time (seconds): an older build directory gets the tests_<label> targets too.
    # -O1 -g1: ASan's recommended optimisation and line tables only, so that a fresh machine builds the
    # unit and stat executables in about half the time (CI's time, docs/reliability.md).
    cmake -S "$root" -B "$asan" "${common[@]}" -DVOLGUIDE_SANITIZE=address,undefined \
      -DVOLGUIDE_SANITIZE_DEBUG=-g1 "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -DNDEBUG" > /dev/null
  else
    echo "test-sanitize: SANITIZE_ASAN_BUILD=$asan_build: expected gcc or fuzz" >&2
    exit 1
  fi
  # Labels among unit|stat|integration: only their executables (tests_<label>, tests/CMakeLists.txt);
  # anything else: every target.
  targets=()
  if [[ $labels =~ ^(unit|stat|integration)(\|(unit|stat|integration))*$ ]]; then
    IFS='|' read -ra picked <<< "$labels"
    for l in "${picked[@]}"; do targets+=(--target "tests_$l"); done
  fi
  cmake --build "$asan" -j "$jobs" "${targets[@]}"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
  export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
  ctest --test-dir "$asan" --output-on-failure -j "$jobs" -L "$labels" -E "$slow" --timeout 1500
fi

if [[ " $stages " == *" tsan "* ]]; then
  [[ -f $tsan/CMakeCache.txt ]] || cmake -S "$root" -B "$tsan" "${common[@]}" -DVOLGUIDE_SANITIZE=thread
  cmake --build "$tsan" -j "$jobs" --target volguide_cli replay_sample tests_tsan
  # Debian's libtbb and libembree are not built with TSan: volguide's side of their hand-overs is
  # annotated (src/volguide/core/parallel.h), tests/sanitizers/tsan.supp lists what is left inside
  # them (docs/reliability.md). history_size=7: the longest per-thread history, so that the previous
  # access of a report has its stack (the suppressions match it).
  export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:history_size=7:suppressions=$root/tests/sanitizers/tsan.supp
  # The gtest suites of those files (tests_tsan, label tsan; ctest names are Suite.Test); Parallel
  # checks the annotations, Checkpoint the checkpoint writer called between the threaded passes.
  ctest --test-dir "$tsan" --output-on-failure -j "$jobs" -L tsan -R '^(Parallel|RenderLoop|Checkpoint|PhotonPass|GuidedVolPath|Determinism)\.' \
    --timeout 1500
fi
