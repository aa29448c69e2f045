#!/usr/bin/env bash
# Fails when a tracked C++ file (.h/.cpp, tests/data excluded) is not formatted with the repo's
# .clang-format; prints the offending lines. Fix with: scripts/check_format.sh --fix
set -euo pipefail
cd "$(dirname "$0")/.."
cf=${CLANG_FORMAT:-clang-format-14}
if ! command -v "$cf" >/dev/null; then echo "check_format: $cf not found"; exit 1; fi
mapfile -t files < <(git ls-files '*.h' '*.cpp' | grep -v '^tests/data/')
if [ "${1:-}" = "--fix" ]; then "$cf" -i "${files[@]}"; exit 0; fi
if "$cf" --dry-run --Werror "${files[@]}"; then
  echo "format ok (${#files[@]} files)"
else
  echo "format violated (see above; scripts/check_format.sh --fix rewrites the files)"; exit 1
fi
