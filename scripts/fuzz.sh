#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan, tests/fuzz) and runs each for N seconds.
#   scripts/fuzz.sh SECONDS [BUILD_DIR] [TARGET...]      (make fuzz FUZZ_SECONDS=N [FUZZ_RUNS=M])
# Seeds: tests/fuzz/corpus/<target>/ (read-only); what the fuzzer adds goes to BUILD_DIR/fuzz-corpus/,
# crashes, hangs and sanitizer reports to BUILD_DIR/fuzz-artifacts/<target>/. Exit 1 when any target
# found something: keep the input in tests/fuzz/regression/<target>/ and fix the reader
# (docs/reliability.md).
set -euo pipefail
seconds=${1:?usage: fuzz.sh SECONDS [BUILD_DIR] [TARGET...]}
build=${2:-build-fuzz}
shift $(( $# >= 2 ? 2 : 1 ))
root=$(cd "$(dirname "$0")/.." && pwd)
all_targets=(scene vol vdb field obj ply exr_part serialized image checkpoint)
if (($#)); then targets=("$@"); else targets=("${all_targets[@]}"); fi
jobs=${JOBS:-$(nproc)}

# Only the fuzz targets are built (the readers and what they need); the same build directory also
# builds the unit and stat tests for CI's ASan + UBSan stage (scripts/test-sanitize.sh).
"$root/scripts/configure-fuzz.sh" "$build"
cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"

# Allocations sized by input are bounded by this budget (core/memory.h), so a size the readers accept
# stays inside -rss_limit_mb below instead of being reported as out-of-memory.
export VOLGUIDE_MEMORY_LIMIT_MB=1024
# One target per core at a time (FUZZ_JOBS, default JOBS): each libFuzzer process is single-threaded,
# so the smoke run's seven 30 s targets take four rounds on two cores instead of seven.
fuzz_jobs=${FUZZ_JOBS:-$jobs}
run_target() {
  local t=$1 corpus=$build/fuzz-corpus/$1 artifacts=$build/fuzz-artifacts/$1
  mkdir -p "$corpus" "$artifacts"
  local dict=()
  [[ -f $root/tests/fuzz/$t.dict ]] && dict=(-dict="$root/tests/fuzz/$t.dict")
  # -timeout: an input taking 10 s is a hang; -rss_limit_mb: a reader allocating > 2 GB for a small
  # file is a finding (resources must be bounded before allocation).
  # FUZZ_SEED (default 0: libFuzzer picks one): a fixed seed makes a run explore the same inputs in
  # the same order (CI's smoke run replays the corpus and explores from seed 1, so it fails on a
  # regression, not on a new finding it happened to reach; the long runs pick their own seeds).
  # FUZZ_RUNS (default -1: no cap): stop a target after that many executions, whichever of it and
  # SECONDS comes first (the acceptance's long runs: FUZZ_RUNS=10000000 with SECONDS=3600).
  if "$build/fuzz_$t" -seed="${FUZZ_SEED:-0}" -runs="${FUZZ_RUNS:--1}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$artifacts/" "${dict[@]}" "$corpus" "$root/tests/fuzz/corpus/$t" \
      2>"$build/fuzz-$t.log"; then
    echo 0 > "$build/fuzz-$t.status"
  else
    echo 1 > "$build/fuzz-$t.status"
  fi
}
for t in "${targets[@]}"; do
  rm -f "$build/fuzz-$t.status"
  echo "== fuzz_$t: $seconds s"
  run_target "$t" &
  while (( $(jobs -rp | wc -l) >= fuzz_jobs )); do wait -n || true; done
done
wait
# The reports in the targets' order, whatever order they ended in.
failed=()
for t in "${targets[@]}"; do
  echo "== fuzz_$t"
  if [[ $(cat "$build/fuzz-$t.status" 2>/dev/null) != 0 ]]; then
    failed+=("$t")
    grep -E "ERROR|SUMMARY|Test unit written" "$build/fuzz-$t.log" | head -5 || true
  fi
  grep -E "stat::number_of_executed_units|cov:" "$build/fuzz-$t.log" | tail -2 || true
done
if ((${#failed[@]})); then
  echo "fuzz: findings in ${failed[*]} (inputs under $build/fuzz-artifacts/, logs $build/fuzz-<target>.log)" >&2
  exit 1
fi
echo "fuzz: no findings in ${targets[*]}"
