#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang (build-fuzz/, SHAPEPRESS_FUZZ=ON) and runs
# each for SECONDS (default 60) on its seed corpus in tests/fuzz/corpus/<target>/. New inputs
# go to build-fuzz/corpus/<target>/ (the repository's corpus stays small); a crash is written
# to build-fuzz/findings/<target>/ and the script exits 1 after running the rest. Keep a fixed
# crash as a regression case in tests/fuzz/regressions/<target>/ (replayed by the unit tests).
#   scripts/fuzz.sh [SECONDS] [TARGET...]
# CI (.ci/run) runs `scripts/fuzz.sh 15 config csv checkpoint mesh image hdf5`: every target
# briefly, on the seed corpus (hdf5's holds files of layout 2 only: fixed-length strings,
# checksummed; the variable-length strings of layout 1 make HDF5 1.10.8 itself fail,
# tests/fuzz/library-crashes).
# -timeout=60: one input running a minute is a finding (a hang), not 20 minutes of CI.
set -uo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(config csv checkpoint mesh image hdf5)
launcher=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(cd .. && pwd)}"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DSHAPEPRESS_FUZZ=ON -DSHAPEPRESS_TESTS=OFF \
  -DSHAPEPRESS_BENCHMARKS=OFF "${launcher[@]}" >/dev/null || exit 2
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]/#/fuzz_}" || exit 2
built=$(date +%s)
echo "fuzz.sh: build took $((built - start)) s"
status=0
for target in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$target" findings="build-fuzz/findings/$target"
  mkdir -p "$corpus" "$findings"
  # -rss_limit_mb: the image decoders may allocate a large picture a header announces.
  # max_allocation_size_mb + allocator_may_return_null: an allocation above the RSS limit fails
  # as it would on a machine without the memory (the library reports an error, ours throws
  # std::bad_alloc, a finding) instead of ending the run as an out-of-memory finding: HDF5
  # allocates whatever a damaged variable-length string claims (tests/fuzz/library-crashes).
  if ! ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1:max_allocation_size_mb=2048 \
    "build-fuzz/tests/fuzz/fuzz_$target" "$corpus" \
    "tests/fuzz/corpus/$target" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 \
    -timeout=60 \
    -artifact_prefix="$findings/" -print_final_stats=1 2>"build-fuzz/fuzz_$target.log"; then
    echo "fuzz_$target: a finding in $findings (log build-fuzz/fuzz_$target.log)"
    status=1
  fi
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "build-fuzz/fuzz_$target.log" |
    sed "s/^/fuzz_$target: /"
done
echo "fuzz.sh: ${#targets[@]} targets ran ${seconds} s each in $(( $(date +%s) - built )) s"
exit $status
