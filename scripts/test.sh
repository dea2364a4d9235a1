#!/usr/bin/env bash
# Builds clpt and runs the whole test suite on the PoCL CPU device.
# Installs missing dependencies first (idempotent), so it works on a fresh Debian 12.
# Then the sanitizer build (scripts/test-sanitize.sh: ASan + UBSan, running the tests that
# feed clpt hostile input); CLPT_SKIP_SANITIZE=1 leaves it out for a quicker local run.
# Arguments go to the first ctest only.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release  # CMakePresets.json: build/, Release, Ninja
cmake --build --preset release
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" "$@"
if [ "${CLPT_SKIP_SANITIZE:-0}" != 1 ]; then
  scripts/test-sanitize.sh
fi
