#!/usr/bin/env bash
# clang-tidy with the repository's .clang-tidy over our C++ sources, using the compile
# database of BUILD_DIR (default: build; scripts/build.sh writes it). Any finding fails.
#   bash scripts/tidy.sh          the .cpp files changed (committed or not) since TIDY_BASE
#                                 (default: the merge base with origin/main, else main), as CI runs it
#   bash scripts/tidy.sh --all    every .cpp file (minutes per core: each file parses protobuf,
#                                 CLI11, spdlog... headers)
#   bash scripts/tidy.sh FILE...  those files
# CUDA sources are left out: clang-tidy cannot read nvcc's command lines. Headers are checked
# through the .cpp files that include them (HeaderFilterRegex in .clang-tidy).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
tidy=$(command -v clang-tidy-14 || command -v clang-tidy || true)
[[ -n $tidy ]] || { echo "tidy: clang-tidy not found (Debian package clang-tidy)" >&2; exit 1; }
[[ -f $build/compile_commands.json ]] || { echo "tidy: no $build/compile_commands.json (run scripts/build.sh)" >&2; exit 1; }
cd "$root"

if [[ ${1:-} == --all ]]; then
  mapfile -t files < <(git ls-files '*.cpp')
elif (($# > 0)); then
  files=("$@")
else
  base=${TIDY_BASE:-}
  for ref in origin/main main; do
    if [[ -z $base ]] && git rev-parse -q --verify "$ref" >/dev/null; then
      base=$(git merge-base "$ref" HEAD)
    fi
  done
  files=()
  # No main branch (an archive, not a clone): nothing to compare against.
  if [[ -n $base ]]; then
    mapfile -t files < <(git diff --name-only --diff-filter=d "$base" -- '*.cpp')
  fi
fi
if ((${#files[@]} == 0)); then
  echo "tidy: no C++ sources to check"
  exit 0
fi
echo "tidy: ${#files[@]} file(s)"
printf '%s\n' "${files[@]}" |
  xargs -P "${JOBS:-$(nproc)}" -n 1 "$tidy" -p "$build" --quiet --warnings-as-errors='*' 2>/dev/null
echo "tidy: clean"
