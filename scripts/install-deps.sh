#!/usr/bin/env bash
# Installs every build, test and benchmark dependency of slamkit from Debian packages.
# Idempotent: packages already present are skipped. Works as root or through sudo.
#   scripts/install-deps.sh            # everything (build, tests, benchmarks, fuzzing, browser test)
#   SLAMKIT_MINIMAL_DEPS=1 scripts/install-deps.sh   # only what the library and CLI need to build
#   SLAMKIT_PEER_DEPS=1 scripts/install-deps.sh      # also the optional MRPT benchmark peer
set -euo pipefail

core=(build-essential cmake ninja-build pkg-config
      libeigen3-dev libsuitesparse-dev libopenblas-dev libmetis-dev
      libcli11-dev nlohmann-json3-dev
      libopencv-dev)               # vio front end (KLT, F-matrix RANSAC, image I/O)
extra=(libgtest-dev libgmock-dev libbenchmark-dev
       libceres-dev                 # benchmark peer only
       clang libclang-rt-14-dev     # libFuzzer + sanitizers for the fuzz targets
       chromium                     # headless rendering test of the HTML report
       python3 git
       python3-dev pybind11-dev python3-numpy python3-pytest)  # the slamkit Python module

peers=(libmrpt-dev)                # optional benchmark peer (EKF-SLAM 2D); large, so opt-in

wanted=("${core[@]}")
if [[ "${SLAMKIT_MINIMAL_DEPS:-0}" != 1 ]]; then wanted+=("${extra[@]}"); fi
if [[ "${SLAMKIT_PEER_DEPS:-0}" == 1 ]]; then wanted+=("${peers[@]}"); fi

missing=()
for pkg in "${wanted[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#wanted[@]} packages already installed"
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then sudo=(); elif command -v sudo >/dev/null; then sudo=(sudo); else
  echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1
fi

echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"

# CHOLMOD's supernodal factorization runs on whatever libblas.so.3 points to; prefer OpenBLAS.
for alt in libblas.so.3 liblapack.so.3; do
  arch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)
  target=$(update-alternatives --list "${alt}-${arch}" 2>/dev/null | grep -m1 openblas || true)
  if [[ -n "$target" ]]; then "${sudo[@]}" update-alternatives --set "${alt}-${arch}" "$target" >/dev/null; fi
done
echo "install-deps: done (BLAS: $(readlink -f /usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)/libblas.so.3))"
