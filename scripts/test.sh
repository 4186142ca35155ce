#!/usr/bin/env bash
# Install dependencies, build, run every test (ctest); then a fuzz smoke
# (a few seconds per loader) and the C ABI's C tests under ASan + UBSan.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j2)
bash scripts/fuzz.sh 5 --runs 50000
bash scripts/sanitize.sh asan --abi-only
