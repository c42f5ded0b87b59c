#!/usr/bin/env bash
# Installs the Debian bookworm packages infocus needs to build and test.
# Idempotent: packages already installed are skipped. Works as root or through sudo.
# Usage: scripts/install-deps.sh [--vm]   (--vm adds what the real-driver VM tier needs)
set -euo pipefail

pkgs=(meson ninja-build pkg-config g++ clang-format
	libopencv-dev libcamera-dev catch2 libturbojpeg0-dev libjpeg-dev libpng-dev
	libcli11-dev nlohmann-json3-dev libncurses-dev tmux libcpp-httplib-dev
	chromium chromium-driver python3-selenium
	libsdl2-dev libimgui-dev xvfb x11-apps imagemagick
	clang libclang-rt-dev) # clang: the fuzzers (scripts/fuzz.sh) and --sanitize=clang
pkgs+=(gnuplot-nox)  # tests only: scripts/soak.sh plots its samples (suite soak)
if [[ "${1:-}" == "--vm" ]]; then
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
