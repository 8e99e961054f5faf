#!/usr/bin/env bash
# Installs what Fulcrum needs from Debian's packages, and only what is missing.
# Idempotent: a second run installs nothing. Usage: scripts/install-deps.sh [extra-package ...]
set -euo pipefail

packages=(cmake g++ make libgtest-dev libgmock-dev libbenchmark-dev nlohmann-json3-dev libcli11-dev libtinygltf-dev zlib1g-dev libtinyxml2-dev libassimp-dev
          pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-setuptools python3-venv python3-pip
          python3-dask python3-distributed
          # The second compiler (the sanitizer pass of scripts/test.sh, docs/determinism.md)
          # and the fuzz build (scripts/fuzz.sh): clang and libFuzzer, cached
          clang libclang-rt-dev ccache "$@")
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
