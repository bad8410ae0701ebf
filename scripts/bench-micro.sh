#!/usr/bin/env bash
# `make bench-micro`: runs every Google Benchmark binary (kernels, whole renders) and stores the results
# under bench/results/<date>/ with the machine description, so each figure has the command that
# reproduced it. (`make bench` is the equal-time relMSE benchmark: scripts/bench.sh.)
set -euo pipefail
build_dir=${1:-build}
out="bench/results/$(date -u +%F)-micro"
mkdir -p "$out"
{
  echo "date: $(date -u +%FT%TZ)"
  echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  echo "cores: $(nproc)"
} > "$out/machine.txt"
shopt -s nullglob
for bin in "$build_dir"/bench_*; do
  [ -x "$bin" ] || continue
  name=$(basename "$bin")
  echo "== $name" >&2
  "$bin" --benchmark_out="$out/$name.json" --benchmark_out_format=json | tee "$out/$name.txt"
done
echo "results in $out" >&2
