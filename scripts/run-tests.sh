#!/usr/bin/env bash
# The README's test command and what CI runs (.ci/run calls this script): installs what is
# missing, checks the C++ formatting (scripts/check-format.sh, first: it fails in seconds),
# builds, and runs the unit, validation (reduced sizes) and end-to-end tests.
# Full-size validation studies: SHAPEPRESS_FULL_VALIDATION=1 scripts/run-tests.sh
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
scripts/install-deps.sh
scripts/check-format.sh
scripts/build.sh
built=$(date +%s)
echo "run-tests.sh: build took $((built - start)) s"
ctest --test-dir build -L 'unit|validation|e2e' --output-on-failure -j"$(nproc)" --timeout 1500
echo "run-tests.sh: tests took $(( $(date +%s) - built )) s, total $(( $(date +%s) - start )) s"
