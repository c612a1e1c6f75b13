#!/usr/bin/env bash
# Configures (once) and builds the given targets (default: everything) in build/, Release.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
jobs=$(nproc 2>/dev/null || echo 2)
if [ $# -eq 0 ]; then
  cmake --build "$build" -j "$jobs"
else
  for t in "$@"; do cmake --build "$build" -j "$jobs" --target "$t"; done
fi
