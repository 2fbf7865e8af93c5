#!/usr/bin/env bash
# clang-format with the repository's .clang-format over every tracked C++ and CUDA source.
#   bash scripts/format.sh          check: names each file that differs from its formatted form, exits 1
#   bash scripts/format.sh --fix    rewrite those files in place
# Formatting differs between clang-format releases, so the check runs with release 14 (Debian 12's
# clang-format, the one the tree is formatted with) and is skipped, saying so, with any other.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
want=14
fmt=$(command -v clang-format-$want || command -v clang-format || true)
[[ -n $fmt ]] || { echo "format: clang-format not found (Debian package clang-format)" >&2; exit 1; }
have=$("$fmt" --version | sed -nE 's/.*version ([0-9]+)\..*/\1/p')
if [[ $have != "$want" ]]; then
  echo "format: skipped: $fmt is release $have, the tree is formatted with release $want" >&2
  exit 0
fi
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.cu' '*.cuh')
if [[ ${1:-} == --fix ]]; then
  printf '%s\n' "${files[@]}" | xargs "$fmt" -i
  exit 0
fi
bad=$(printf '%s\n' "${files[@]}" | xargs "$fmt" --dry-run 2>&1 | sed -nE 's/^([^:]+):[0-9]+:[0-9]+: (warning|error):.*/\1/p' | sort -u)
if [[ -n $bad ]]; then
  echo "format: $(wc -l <<<"$bad") file(s) differ from clang-format's output (bash scripts/format.sh --fix):" >&2
  printf '  %s\n' $bad >&2
  exit 1
fi
echo "format: ${#files[@]} files clean"
