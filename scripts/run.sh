#!/usr/bin/env bash
# Command 1: install what is missing, build `immerse` (Release), run the main job on the bundled
# default input (the paper's Fig. 6 curve), writing into out/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" immerse
cd "$root"
exec "$root/build/immerse" "$@"
