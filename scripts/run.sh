#!/usr/bin/env bash
# Installs what is missing, builds, and runs infocus's main job on the built-in default.
# Extra arguments replace the default command: scripts/run.sh dof --focal 50mm --fnumber 8 --focus 10m
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here" || exit 1
scripts/install-deps.sh || exit 1
[[ -f build/build.ninja ]] || meson setup build >/dev/null || exit 1
ninja -C build >/dev/null || ninja -C build || exit 1
if [[ $# -gt 0 ]]; then
	exec build/src/cli/infocus "$@"
fi
# The main job until the live assistant exists: per-region sharpness and blur width of the
# built-in simulated camera (three planes at known depths), as a table.
exec build/src/cli/infocus analyze "sim:scene=steps" --frames 1 --grid 8x4 --format table
