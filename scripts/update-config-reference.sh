#!/usr/bin/env bash
# Regenerates docs/config-reference.md from the stages' option tables (a test fails when the
# checked-in file differs). Builds first; extra arguments go to scripts/build.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh "$@"
build/app/shapepress help-config --markdown > docs/config-reference.md.new
mv docs/config-reference.md.new docs/config-reference.md
