#!/usr/bin/env bash
# Installs the Debian bookworm packages infocus needs to build and run, and with --test what its
# tests need too. Idempotent: packages already installed are skipped. Works as root or through sudo.
# Usage: scripts/install-deps.sh [--test] [--vm]
#   (none)  building and running infocus (scripts/run.sh)
#   --test  also the test machinery: a terminal multiplexer, a browser and its driver, a virtual
#           display, the formatter, clang for the fuzzers (scripts/test.sh)
#   --vm    also what the real-driver VM tier needs (tests/vm/run.sh)
set -euo pipefail

# Building and running: the compiler and build tools, and the libraries of every part and face.
pkgs=(meson ninja-build pkg-config g++
	libopencv-dev libcamera-dev catch2 libturbojpeg0-dev libjpeg-dev libpng-dev zlib1g-dev
	libcli11-dev nlohmann-json3-dev libncurses-dev libcpp-httplib-dev
	libsdl2-dev libimgui-dev)
test_pkgs=(clang-format tmux
	chromium chromium-driver python3-selenium
	xvfb x11-apps imagemagick
	clang libclang-rt-dev) # clang: the fuzzers (scripts/fuzz.sh) and --sanitize=clang
# The Python module (src/py): pybind11 and Python's headers to build it, NumPy to run it.
pkgs+=(pybind11-dev python3-dev python3-numpy)
# Running infocus-batch (src/py/infocus/batch): Dask distributed, its local cluster, scheduler and
# workers (brings python3-dask); without it only infocus-batch is missing.
pkgs+=(python3-distributed)
# Tests only: the Python module's suite, and OpenCV from Python for the bench's python baseline.
test_pkgs+=(python3-pytest python3-opencv)
# The focusmeter element (src/gstreamer): GStreamer's headers to build it, its tools and base and
# good plugins to run it (gst-launch-1.0, videotestsrc, jpegdec, v4l2src).
pkgs+=(libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev
	gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-good)
# Tests only: focusmeter's bus read from Python.
test_pkgs+=(python3-gi gir1.2-gstreamer-1.0 gir1.2-gst-plugins-base-1.0)
# Tests only: scripts/soak.sh plots its samples.
test_pkgs+=(gnuplot-nox)
for arg in "$@"; do
	case $arg in
	--test) pkgs+=("${test_pkgs[@]}") ;;
	--vm) ;;
	*) echo "install-deps: unknown option '$arg'; use --test and/or --vm" >&2; exit 2 ;;
	esac
done
if [[ " $* " == *" --vm "* ]]; then
	pkgs+=(qemu-system-x86 linux-image-amd64 busybox-static v4l-utils cpio
		linux-source-6.1 libcamera-ipa libcamera-tools udev xz-utils make bc
		flex bison libelf-dev libssl-dev linux-headers-amd64)
fi

missing=()
for p in "${pkgs[@]}"; do
	if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
		missing+=("$p")
	fi
done
if [[ ${#missing[@]} -eq 0 ]]; then
	echo "install-deps: all ${#pkgs[@]} packages already installed" >&2
	exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
	sudo=()
elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
	sudo=(sudo -n)
else
	echo "install-deps: missing packages: ${missing[*]}" >&2
	echo "install-deps: need root to install them; run as root or give this user password-less sudo," >&2
	echo "              or install them yourself: apt-get install ${missing[*]}" >&2
	exit 1
fi

echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
