#!/usr/bin/env bash
# Installs every Debian package the project needs
# (docs/architecture.md, "Build and dependencies").
# Idempotent and quiet: it only calls apt-get when something is missing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev
  libtinygltf-dev libtbb-dev libopenmpi-dev openmpi-bin googletest libgtest-dev libbenchmark-dev libcli11-dev
  nlohmann-json3-dev libtorch-dev libopenblas0-openmp python3-matplotlib
  pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest
  chromium chromium-driver python3-selenium
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
