#!/usr/bin/env bash
# clang-tidy with the repository's .clang-tidy over our C++ sources, using the compile
# database of BUILD_DIR (default: build; scripts/build.sh writes it). Any finding fails.
#   bash scripts/tidy.sh          the lines of .cpp files changed (committed or not) since
#                                 TIDY_BASE (default: the merge base with origin/main, else main),
#                                 as CI runs it: code a change did not touch never fails it
#   bash scripts/tidy.sh --all    every line of every .cpp file (minutes per core: each file
#                                 parses protobuf, CLI11, spdlog... headers)
#   bash scripts/tidy.sh FILE...  every line of those files
# The changed-lines run checks nothing when there is no base to compare with (an archive, a
# shallow clone without main's history, or main itself: its merge base with main is HEAD), and
# at most TIDY_MAX_FILES files (default 20; a larger change names the rest and skips them) with
# TIDY_TIMEOUT seconds per file (default 300), so that it stays within minutes on 2 cores.
# CUDA sources are left out: clang-tidy cannot read nvcc's command lines. Headers are checked
# through the .cpp files that include them (HeaderFilterRegex in .clang-tidy) by --all and FILE.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
jobs=${JOBS:-$(nproc)}
tidy=$(command -v clang-tidy-14 || command -v clang-tidy || true)
[[ -n $tidy ]] || { echo "tidy: clang-tidy not found (Debian package clang-tidy)" >&2; exit 1; }
[[ -f $build/compile_commands.json ]] || { echo "tidy: no $build/compile_commands.json (run scripts/build.sh)" >&2; exit 1; }
cd "$root"

if (($# > 0)); then
  if [[ $1 == --all ]]; then mapfile -t files < <(git ls-files '*.cpp'); else files=("$@"); fi
  echo "tidy: ${#files[@]} file(s)"
  printf '%s\n' "${files[@]}" |
    xargs -P "$jobs" -n 1 "$tidy" -p "$build" --quiet --warnings-as-errors='*' 2>/dev/null
  echo "tidy: clean"
  exit 0
fi

# The newer of the merge bases with origin/main and main (a local main may be ahead of a
# stale origin/main, a CI clone may have only origin/main).
base=${TIDY_BASE:-}
if [[ -z $base ]]; then
  for ref in origin/main main; do
    git rev-parse -q --verify "$ref^{commit}" >/dev/null || continue
    b=$(git merge-base "$ref" HEAD 2>/dev/null) || continue
    if [[ -z $base ]] || git merge-base --is-ancestor "$base" "$b"; then base=$b; fi
  done
fi
if [[ -z $base ]]; then
  echo "tidy: no main branch with a common history to compare with; nothing checked"
  exit 0
fi
mapfile -t files < <(git diff --name-only --diff-filter=d "$base" -- '*.cpp')
if ((${#files[@]} == 0)); then
  echo "tidy: no C++ sources changed since $(git rev-parse --short "$base")"
  exit 0
fi
max=${TIDY_MAX_FILES:-20}
if ((${#files[@]} > max)); then
  echo "tidy: ${#files[@]} changed files, checking the first $max; not checked: ${files[*]:max}"
  files=("${files[@]:0:max}")
fi
echo "tidy: changed lines of ${#files[@]} file(s) since $(git rev-parse --short "$base")"
# clang-tidy-diff (Debian's clang-tidy package) reports findings on changed lines only; it
# exits 0 either way, so its output decides.
diff_tool=$(command -v clang-tidy-diff-14.py || command -v clang-tidy-diff || true)
[[ -n $diff_tool ]] || { echo "tidy: clang-tidy-diff not found (Debian package clang-tidy)" >&2; exit 1; }
out=$(git diff -U0 "$base" -- "${files[@]}" |
  python3 "$diff_tool" -p1 -path "$build" -clang-tidy-binary "$tidy" -j "$jobs" -quiet \
    -timeout "${TIDY_TIMEOUT:-300}" -regex '.*\.cpp' 2>/dev/null || true)
if grep -qE '^[^ ]+:[0-9]+:[0-9]+: (warning|error):' <<<"$out"; then
  printf '%s\n' "$out"
  exit 1
fi
echo "tidy: clean"
