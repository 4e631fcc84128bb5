#!/usr/bin/env bash
# The README's demo command: installs what is missing, builds, and runs the embedded demo study
# (pipelines/demo/Makefile) into demo-out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
make -C pipelines/demo -j"$(nproc)" SHAPEPRESS="$PWD/build/app/shapepress" OUT="$PWD/demo-out"
echo "run-demo.sh: results in $PWD/demo-out"
