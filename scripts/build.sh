#!/usr/bin/env bash
# Configures (once) and builds the given targets (default: everything) in build/, Release.
# Quiet when nothing changed; the full compiler output goes to build/build.log and is shown
# only when the build fails.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
mkdir -p "$build"
log="$build/build.log"
if [ ! -f "$build/CMakeCache.txt" ]; then
  echo "configuring build/ (Release)" >&2
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$log" 2>&1 || { cat "$log" >&2; exit 1; }
fi
jobs=${IMM_JOBS:-$(nproc 2>/dev/null || echo 2)}
targets=()
for t in "$@"; do targets+=(--target "$t"); done
if ! cmake --build "$build" -j "$jobs" "${targets[@]}" >"$log" 2>&1; then
  cat "$log" >&2
  exit 1
fi
if grep -q "Building CXX" "$log"; then
  echo "built: $(grep -c 'Building CXX' "$log") translation units (log: build/build.log)" >&2
fi
