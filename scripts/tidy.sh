#!/usr/bin/env bash
# clang-tidy with the repository's .clang-tidy over our C++ sources, using the compile
# database of BUILD_DIR (default: build; scripts/build.sh writes it). Any finding fails.
#   bash scripts/tidy.sh          the .cpp files changed since TIDY_BASE (default: origin/main when
#                                 it exists and differs from HEAD, else HEAD~1), as CI runs it
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
  if [[ -z $base ]]; then
    if git rev-parse -q --verify origin/main >/dev/null && [[ $(git rev-parse origin/main) != $(git rev-parse HEAD) ]]; then
      base=$(git merge-base origin/main HEAD)
    else
      base=HEAD~1
    fi
  fi
  mapfile -t files < <(git diff --name-only --diff-filter=d "$base" -- '*.cpp')
fi
if ((${#files[@]} == 0)); then
  echo "tidy: no C++ sources to check"
  exit 0
fi
echo "tidy: ${#files[@]} file(s)"
printf '%s\n' "${files[@]}" |
  xargs -P "${JOBS:-$(nproc)}" -n 1 "$tidy" -p "$build" --quiet --warnings-as-errors='*' 2>/dev/null
echo "tidy: clean"
