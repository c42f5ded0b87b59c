#!/usr/bin/env bash
# Installs what is missing, builds, and runs infocus's main job: the live focus assistant.
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
# The main job: the live focus assistant. On a terminal, the terminal meter on the first camera
# (or the simulated camera when there is none); without one, the text meter for 10 seconds.
if [[ -t 0 && -t 1 ]]; then
	exec build/src/cli/infocus live
fi
exec build/src/cli/infocus live --ui text --seconds 10
