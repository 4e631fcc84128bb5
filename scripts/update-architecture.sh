#!/usr/bin/env bash
# Regenerates the stage-links table in docs/architecture.md from the CMake targets' links (a
# test fails when the checked-in table differs). Configures build/ first.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build >/dev/null
cmake -DLINKS=build/stage_links.cmake -DDOC=docs/architecture.md -DWRITE_DOC=ON \
  -P tests/architecture/check_includes.cmake
