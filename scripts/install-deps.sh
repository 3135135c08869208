#!/usr/bin/env bash
# Installs the Debian 12 packages woven needs, only those that are missing (idempotent).
set -euo pipefail
packages=(cmake ninja-build g++ make pkg-config
  libeigen3-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
  libtinygltf-dev libssl-dev python3-jsonschema python3-meshio assimp-utils
  libstb-dev libembree-dev libtbb-dev libsuitesparse-dev libopenblas0-pthread
  libgtest-dev libgmock-dev libbenchmark-dev time libbullet-dev
  clang libclang-rt-14-dev
  python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-pil
  python3-setuptools python3-wheel python3-pip python3-venv
  openmpi-bin chromium libjs-three libcairo2-dev fonts-dejavu-core)
missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi
if [[ $(id -u) -ne 0 ]]; then
  echo "woven: missing Debian packages: ${missing[*]}" >&2
  echo "woven: run as root (or with sudo): apt-get update && apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "woven: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
