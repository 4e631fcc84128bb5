#!/usr/bin/env bash
# Configures and builds shapepress (Release, warnings as errors) into build/.
# Extra arguments go to cmake's configure step, e.g. -DSHAPEPRESS_NATIVE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHAPEPRESS_WERROR=ON "$@" >/dev/null
cmake --build build -j"$(nproc)"
