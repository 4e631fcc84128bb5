#!/usr/bin/env bash
# Fails, naming the files, when a C++ file of the repository (*.cpp, *.hpp; not build/) is not
# as clang-format writes it with the repository's .clang-format. scripts/run-tests.sh runs it
# before building, so CI fails fast on formatting. Fix: clang-format -i FILE...
set -euo pipefail
cd "$(dirname "$0")/.."
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  # Tracked and new (not ignored) files: build/ is ignored.
  mapfile -t files < <(git ls-files --cached --others --exclude-standard -- '*.cpp' '*.hpp')
else
  mapfile -t files < <(find . -path ./build -prune -o -type f \( -name '*.cpp' -o -name '*.hpp' \) -print)
fi
# One clang-format for all files; its diagnostics start with the file's name.
status=0
report=$(clang-format --dry-run -Werror "${files[@]}" 2>&1) || status=$?
if [[ $status -eq 0 ]]; then
  echo "check-format.sh: ${#files[@]} C++ files formatted"
  exit 0
fi
mapfile -t unformatted < <(sed -n 's/^\(.*\.[ch]pp\):[0-9]*:[0-9]*: error: .*/\1/p' <<<"$report" | sort -u)
if [[ ${#unformatted[@]} -eq 0 ]]; then  # clang-format itself failed
  echo "$report" >&2
  exit 1
fi
echo "check-format.sh: ${#unformatted[@]} file(s) not clang-formatted (run clang-format -i on them):" >&2
printf '  %s\n' "${unformatted[@]}" >&2
exit 1
