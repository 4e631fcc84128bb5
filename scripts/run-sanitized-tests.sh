#!/usr/bin/env bash
# Builds with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and runs the unit
# tests there (slow; on demand, not part of CI).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# No -Werror here: with the sanitizers g++ 12 reports false "maybe-uninitialized" warnings inside
# libstdc++'s <regex> and <functional>; the Release build (CI) keeps warnings as errors.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHAPEPRESS_SANITIZE=ON \
      -DSHAPEPRESS_WERROR=OFF -DSHAPEPRESS_BENCHMARKS=OFF >/dev/null
cmake --build build-asan -j"$(nproc)"
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan -L unit --output-on-failure -j"$(nproc)"
