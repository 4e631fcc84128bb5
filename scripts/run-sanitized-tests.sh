#!/usr/bin/env bash
# Builds with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and runs the tests
# of the ctest labels LABELS there (default 'unit|e2e': the unit and end-to-end tests; the
# validation studies would take hours under the sanitizers). On demand, not in CI (.ci/run): its
# minutes are in docs/measurements.md, "CI's minutes".
#   scripts/run-sanitized-tests.sh [LABELS]
set -euo pipefail
cd "$(dirname "$0")/.."
labels="${1:-unit|e2e}"
start=$(date +%s)
scripts/install-deps.sh
launcher=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# No -Werror here: with the sanitizers g++ 12 reports false "maybe-uninitialized" warnings inside
# libstdc++'s <regex> and <functional>; the Release build (CI) keeps warnings as errors.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHAPEPRESS_SANITIZE=ON \
      -DSHAPEPRESS_WERROR=OFF -DSHAPEPRESS_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
# Only what the labels run: the binary the end-to-end tests call and one test executable per
# (label, stage) (tests/CMakeLists.txt), not the validation studies.
targets=(shapepress)
for label in ${labels//|/ }; do
  for stage in tests/"$label"/*/; do
    targets+=("${label}_$(basename "$stage")")
  done
done
cmake --build build-asan -j"$(nproc)" --target "${targets[@]}"
built=$(date +%s)
echo "run-sanitized-tests.sh: build took $((built - start)) s"
# -fno-sanitize-recover=all (cmake/ShapepressWarnings.cmake): a UBSan report fails the test.
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan -L "$labels" --output-on-failure -j"$(nproc)" --timeout 1500
echo "run-sanitized-tests.sh: tests ($labels) took $(( $(date +%s) - built )) s"
