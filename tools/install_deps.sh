#!/usr/bin/env bash
# Installs the Debian packages plume's build, tests and benchmarks need, but
# only those that are missing. Run as root (or with sudo available); as an
# ordinary user it only reports what is missing.
set -euo pipefail

packages=(
  cmake ninja-build g++ clang libclang-rt-14-dev
  libxsimd-dev libeigen3-dev catch2 libbenchmark-dev
  libsleef-dev libglm-dev libembree-dev libmpfr-dev libtinyobjloader-dev
  python3 python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "plume: missing packages: ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo apt-get update -qq
  sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "plume: run as root (or install them) to continue" >&2
  exit 1
fi
