#!/usr/bin/env bash
# Installs every Debian package facesr uses. Idempotent: prints nothing and
# exits 0 when everything is already present.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake pkg-config git
  # geometry and linear algebra (Spectra: sparse eigenproblems for the
  # spectral error split of `facesr eval`)
  libeigen3-dev libtet1.5-dev libcgal-dev libgmp-dev libmpfr-dev libspectra-dev
  # ray casting (collisions, previews)
  libembree-dev
  # OpenCL: PoCL CPU device, ICD loader, headers
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers
  # training only. LibTorch calls the system BLAS; without OpenBLAS that is
  # the single-threaded reference BLAS, several times slower on the same matmuls.
  libtorch-dev libopenblas0-openmp
  # I/O and CLI
  nlohmann-json3-dev libcli11-dev libstb-dev
  # tests and benchmarks; clang with its sanitizer runtimes (libFuzzer) for
  # scripts/fuzz.sh
  libgtest-dev libgmock-dev libbenchmark-dev clang libclang-rt-14-dev
  # bindings: C# via mono, Rust via cargo (offline, no crates)
  mono-mcs mono-runtime cargo
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# cargo may come from rustup rather than Debian; accept either.
if command -v cargo >/dev/null 2>&1; then
  missing=("${missing[@]/cargo}")
fi
filtered=()
for p in "${missing[@]}"; do [[ -n "$p" ]] && filtered+=("$p"); done

if [[ ${#filtered[@]} -eq 0 ]]; then
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "install-deps: installing ${filtered[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${filtered[@]}" >/dev/null
echo "install-deps: done" >&2
