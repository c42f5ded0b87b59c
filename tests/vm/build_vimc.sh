#!/usr/bin/env bash
# Builds vimc.ko (not in Debian's kernel) out of tree from Debian's linux-source package.
# Usage: tests/vm/build_vimc.sh KVER OUTDIR   → OUTDIR/vimc.ko (kept between runs)
set -euo pipefail
kver=$1
out=$2
[[ -f "$out/vimc.ko" ]] && exit 0
src=$(ls /usr/src/linux-source-6.1.tar.* 2>/dev/null | head -1)
[[ -n "$src" ]] || { echo "build_vimc: /usr/src/linux-source-6.1.tar.xz missing (package linux-source-6.1)" >&2; exit 1; }
[[ -d /lib/modules/$kver/build ]] || { echo "build_vimc: /lib/modules/$kver/build missing (package linux-headers-$kver)" >&2; exit 1; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar -xf "$src" -C "$work" --wildcards 'linux-source-6.1/drivers/media/test-drivers/vimc/*'
dir="$work/linux-source-6.1/drivers/media/test-drivers/vimc"
make -s -C "/lib/modules/$kver/build" M="$dir" CONFIG_VIDEO_VIMC=m modules >&2
cp "$dir/vimc.ko" "$out/vimc.ko"
