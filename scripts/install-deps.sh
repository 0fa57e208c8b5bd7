#!/usr/bin/env bash
# Installs the Debian 12 packages Saccade builds and runs with, when any is missing, and any
# further packages named as arguments (an optional benchmark's: scripts/bench-peer.sh).
# Idempotent: does nothing (and needs no network) when everything is already there.
set -euo pipefail

packages=(
  cmake make g++ pkg-config ccache iproute2
  libpcl-dev libeigen3-dev libflann-dev
  libopenni2-dev libfreenect-dev libfreenect-bin
  liblcm-dev liblcm-bin libglib2.0-dev
  libtbb-dev libyaml-cpp-dev libopencv-contrib-dev
  libgtest-dev libgmock-dev libbenchmark-dev libpng-dev libtiff-dev
  libcli11-dev libsystemd-dev libssl-dev
  cyclonedds-dev cyclonedds-tools
  liblcm-java liblcm-lua lua5.2 lua-luaossl default-jdk-headless python3 libjchart2d-java
  gnuplot-nox
  libcpp-httplib-dev libjpeg-dev zlib1g-dev chromium
)
# saccade view's 3D view comes from npm (three.js); any npm will do (Debian's, or one that came
# with another Node.js).
command -v npm >/dev/null 2>&1 || packages+=(npm)
packages+=("$@")

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
  [ "$status" = "installed" ] || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "saccade: installing missing Debian packages: ${missing[*]}" >&2
if [ "$(id -u)" -ne 0 ]; then
  echo "saccade: error: packages missing and not root; run as root or install: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
