#!/usr/bin/env bash
# Installs the Debian 12 packages gradmesh needs to build, test and check its outputs.
# Idempotent: does nothing when everything is there. Needs root (or sudo).
set -euo pipefail

packages=(
  cmake ninja-build g++ clang libclang-rt-14-dev pkg-config
  libopenimageio-dev openimageio-tools libwebp-dev libopenexr-dev libjpeg-dev libeigen3-dev libcgal-dev libtinyxml2-dev
  catch2 libzstd-dev zlib1g-dev libopencv-dev
  inkscape ghostscript poppler-utils time parallel
  chromium firefox-esr librsvg2-bin terser
  python3-dev python3-pybind11 python3-numpy python3-pytest python3-distributed
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq "${missing[@]}" >/dev/null
echo "install-deps: done"
