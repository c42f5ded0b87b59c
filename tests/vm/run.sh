#!/usr/bin/env bash
# Real-driver test tier: boots Debian's kernel in qemu with vivid (V4L2) and vimc (libcamera) and
# runs infocus against them. Prints one line per part, then "N passed, N failed".
# Usage: tests/vm/run.sh [BUILD_DIR]    (default: build; built first if it has no infocus)
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-build}
[[ "$build" = /* ]] || build="$root/$build"

die() { echo "vm: cannot run: $*" >&2; echo "0 passed, 1 failed"; exit 1; }

"$root/scripts/install-deps.sh" --vm >&2 || die "the VM packages are missing (scripts/install-deps.sh --vm)"
command -v qemu-system-x86_64 >/dev/null || die "qemu-system-x86_64 not found (package qemu-system-x86)"
[[ -x /bin/busybox ]] || die "static busybox not found (package busybox-static)"

# The kernel to boot: the newest one whose headers are installed (vimc is built against them).
kver=""
for k in $(ls /boot/vmlinuz-* 2>/dev/null | sed 's#/boot/vmlinuz-##' | sort -V -r); do
	if [[ -d /lib/modules/$k/build && -d /lib/modules/$k/kernel/drivers/media ]]; then kver=$k; break; fi
done
[[ -n "$kver" ]] || die "no /boot/vmlinuz-* with matching linux-headers and modules"
[[ -r /boot/vmlinuz-$kver ]] || die "/boot/vmlinuz-$kver is not readable"

# The libcamera backend is a module infocus loads on demand; a build without libcamera has none.
lcmod=drivers/libcamera/infocus-libcamera.so
webmod=src/live/web/infocus-web.so
if [[ ! -x "$build/src/cli/infocus" || ! -x "$build/tests/drivers/infocus_vm_blur_frames" ||
	! -f "$build/$lcmod" || ! -f "$build/$webmod" ]]; then
	[[ -f "$build/build.ninja" ]] || meson setup "$build" "$root" >&2 || die "meson setup failed"
	ninja -C "$build" -t query "$lcmod" >/dev/null 2>&1 || lcmod=""
	ninja -C "$build" -t query "$webmod" >/dev/null 2>&1 || webmod=""
	ninja -C "$build" -j2 src/cli/infocus tests/drivers/infocus_vm_blur_frames \
		tests/drivers/test_drivers_v4l2_device $lcmod $webmod >&2 || die "building infocus failed"
fi

work="$build/vm"
mkdir -p "$work"
"$here/build_vimc.sh" "$kver" "$work/vimc-$kver" || die "building vimc.ko failed"

# --- initramfs ---------------------------------------------------------------------------------
rd="$work/root"
rm -rf "$rd"
mkdir -p "$rd"/{bin,sbin,etc,proc,sys,dev,tmp,run,mods,data}
cp /bin/busybox "$rd/bin/busybox"
for a in sh mount umount insmod sleep echo cat ls kill grep sed head tail wc rm mkdir poweroff \
	seq cut tr ln sync dmesg cmp awk ip wget pidof timeout; do ln -sf busybox "$rd/bin/$a"; done

copy_with_libs() {  # copies a program (unless it is in the initramfs already) and its libraries
	local f=$1
	if [[ $f != "$rd"/* ]]; then
		mkdir -p "$rd$(dirname "$f")"
		cp -L "$f" "$rd$f"
	fi
	ldd "$f" 2>/dev/null | grep -o '/[^ ]*' | while read -r lib; do
		[[ -e "$rd$lib" ]] && continue
		mkdir -p "$rd$(dirname "$lib")"
		cp -L "$lib" "$rd$lib"
	done
}
cp "$build/src/cli/infocus" "$rd/bin/infocus.bin"
copy_with_libs "$rd/bin/infocus.bin"
strip -s "$rd/bin/infocus.bin" 2>/dev/null
# infocus looks for its modules beside its executable first; libcamera comes with the module.
if [[ -f "$build/drivers/libcamera/infocus-libcamera.so" ]]; then
	cp "$build/drivers/libcamera/infocus-libcamera.so" "$rd/bin/"
	copy_with_libs "$rd/bin/infocus-libcamera.so"
	strip -s "$rd/bin/infocus-libcamera.so" 2>/dev/null
fi
copy_with_libs "$(command -v v4l2-ctl)"
copy_with_libs "$(command -v media-ctl)"
# The web face (part i steps the lens through it).
if [[ -f "$build/src/live/web/infocus-web.so" ]]; then
	cp "$build/src/live/web/infocus-web.so" "$rd/bin/"
	copy_with_libs "$rd/bin/infocus-web.so"
	strip -s "$rd/bin/infocus-web.so" 2>/dev/null
fi
[[ -x "$build/tests/drivers/test_drivers_v4l2_device" ]] &&
	cp "$build/tests/drivers/test_drivers_v4l2_device" "$rd/bin/" && copy_with_libs "$rd/bin/test_drivers_v4l2_device"
# The GStreamer element on vivid: gst-launch-1.0 with the two plugins its pipeline uses (the
# core elements for fakesink, video4linux2 for v4l2src) and the build's focusmeter, all in /gst.
gstplug="$build/src/gstreamer/libgstinfocus.so"
if [[ -f "$gstplug" ]]; then
	command -v gst-launch-1.0 >/dev/null || die "gst-launch-1.0 not found (gstreamer1.0-tools)"
	sysplug=$(pkg-config --variable=pluginsdir gstreamer-1.0)
	mkdir -p "$rd/gst"
	for p in "$sysplug/libgstcoreelements.so" "$sysplug/libgstvideo4linux2.so" "$gstplug"; do
		[[ -f "$p" ]] || die "GStreamer plugin $p not found (gstreamer1.0-plugins-good)"
		cp "$p" "$rd/gst/"
		strip -s "$rd/gst/$(basename "$p")" 2>/dev/null
		copy_with_libs "$rd/gst/$(basename "$p")"
	done
	copy_with_libs "$(command -v gst-launch-1.0)"
fi
copy_with_libs /bin/udevadm
copy_with_libs /lib/systemd/systemd-udevd
mkdir -p "$rd/lib/udev" "$rd/etc/udev"
cp -a /lib/udev/rules.d "$rd/lib/udev/"
ipa=/usr/lib/x86_64-linux-gnu/libcamera
mkdir -p "$rd$ipa" "$rd/usr/share/libcamera"
cp -a "$ipa"/ipa_vimc.so* "$ipa"/vimc_ipa_proxy "$rd$ipa/"
for f in "$rd$ipa"/*.so "$rd$ipa"/vimc_ipa_proxy; do copy_with_libs "${f#"$rd"}"; done
cp -a /usr/share/libcamera/ipa "$rd/usr/share/libcamera/" 2>/dev/null

# Only the media modules vivid and vimc need, in dependency order.
: >"$rd/mods/order"
for m in vivid videobuf2-dma-contig videobuf2-vmalloc videobuf2-v4l2 v4l2-tpg mc videodev; do
	modprobe -S "$kver" --show-depends "$m" | awk '$1=="insmod"{print $2}'
done | awk '!seen[$0]++' | while read -r ko; do
	cp "$ko" "$rd/mods/"
	echo "$(basename "$ko")" >>"$rd/mods/order"
done
strip --strip-debug -o "$rd/mods/vimc.ko" "$work/vimc-$kver/vimc.ko"

# The loopback's frames (tests/vm/blur_frames.cpp), and the host's reading of the same pixels,
# which the VM's reading through the driver must match.
frames=(sharp g1 g2 g4 d4 d6 d8)
mkdir -p "$work/frames"
"$build/tests/drivers/infocus_vm_blur_frames" --y4m "$work/frames/blur" probe "${frames[@]}" ||
	die "cannot write the blur frames"
for f in probe "${frames[@]}"; do cp "$work/frames/blur$f.yuyv" "$rd/data/"; done
for f in "${frames[@]}"; do
	"$build/src/cli/infocus" analyze "$work/frames/blur$f.y4m" --grid 3x2 --blur-search all \
		>"$work/frames/host_$f.jsonl" || die "the host cannot analyze $work/frames/blur$f.y4m"
done
cp "$here/init.sh" "$rd/init"
chmod +x "$rd/init"
(cd "$rd" && find . | cpio -o -H newc 2>/dev/null | gzip -1) >"$work/initrd.gz" || die "cannot pack the initramfs"

# --- boot ---------------------------------------------------------------------------------------
log="$work/console.log"
start=$(date +%s)
timeout 600 qemu-system-x86_64 -accel tcg -m 1024 -smp 2 -nographic -no-reboot \
	-kernel "/boot/vmlinuz-$kver" -initrd "$work/initrd.gz" \
	-append "console=ttyS0 quiet loglevel=3 panic=-1" </dev/null >"$log" 2>&1
echo "vm: booted $kver, ran in $(($(date +%s) - start)) s; console log: $log" >&2
grep -q "@@done" "$log" || echo "vm: the VM did not finish (timeout or crash); see $log" >&2

python3 "$here/check.py" "$log" "$work/frames"
