#!/usr/bin/env bash
# The VM loopback's frames read on the host: the engine must read them within the tolerances the VM
# tier holds the loop to (tests/vm/check.py), so that a drift of the engine shows here and a
# failure of the VM tier's part c points at the driver.
# Usage: frames_on_host.sh INFOCUS BLUR_FRAMES   (the infocus and infocus_vm_blur_frames binaries)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
infocus=${1:?infocus binary}
frames_bin=${2:?infocus_vm_blur_frames binary}
command -v python3 >/dev/null || { echo "python3 not found: cannot judge the readings" >&2; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
frames=(sharp g1 g2 g4 d4 d6 d8)
"$frames_bin" --y4m "$tmp/blur" "${frames[@]}"
for f in "${frames[@]}"; do
	# As run.sh reads them: every region searched afresh.
	"$infocus" analyze "$tmp/blur$f.y4m" --grid 3x2 --blur-search all >"$tmp/host_$f.jsonl"
done
python3 "$here/check.py" --host "$tmp"
