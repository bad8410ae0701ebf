#!/usr/bin/env bash
# `make bench`: the equal-time benchmark (bench/run_bench.py) and the headless-Chromium check of its
# HTML report. Arguments after the build directory go to run_bench.py (--quick, --time S, ...).
set -euo pipefail
build_dir=${1:-build}
shift || true
# Debian's interpreter, which has python3-matplotlib (a pyenv or venv python3 earlier in PATH may not).
PYTHON=${PYTHON:-/usr/bin/python3}
out_file=$(mktemp)
trap 'rm -f "$out_file"' EXIT
status=0
"$PYTHON" bench/run_bench.py --build-dir "$build_dir" --print-out-dir "$out_file" "$@" || status=$?
out=$(cat "$out_file")
if [ -n "$out" ] && [ -f "$out/index.html" ]; then
  "$PYTHON" bench/check_report.py "$out/index.html" || status=1
else
  echo "make bench: no report was written" >&2
  status=1
fi
exit $status
