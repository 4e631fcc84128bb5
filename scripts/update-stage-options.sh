#!/usr/bin/env bash
# Regenerates the option tables of docs/stages.md (between its "<!-- options: STAGE -->" and
# "<!-- end options -->" markers) from the stages' option tables (a test fails when the checked-in
# file differs). Builds first; extra arguments go to scripts/build.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh "$@"
build/app/shapepress help-options docs/stages.md > docs/stages.md.new
mv docs/stages.md.new docs/stages.md
