#!/usr/bin/env bash
# Configures and builds shapepress (Release, warnings as errors) into build/.
# Extra arguments go to cmake's configure step, e.g. -DSHAPEPRESS_NATIVE=ON.
# With ccache installed, compiles go through it; CCACHE_BASEDIR makes the cache shared between
# checkouts (git worktrees) of the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHAPEPRESS_WERROR=ON "${launcher[@]}" "$@" >/dev/null
cmake --build build -j"$(nproc)"
