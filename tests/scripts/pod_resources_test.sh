#!/usr/bin/env bash
# scripts/pod_resources.sh on a short fandisk load (CPU engine): it stages nothing itself, so
# fqd and fqstreambench are staged here as a GPU host would get them (scripts/stage.sh), and
# its report line must carry the cores, memory and engine figures read from fqd's /metrics.
#   pod_resources_test.sh SOURCE_DIR FQD FQSTREAMBENCH
set -euo pipefail
src=$1 fqd=$2 bench=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash "$src/scripts/stage.sh" "$tmp/stage" "$fqd" "$bench" >/dev/null
cat "$src/tests/daemon/child_fqd.toml" >"$tmp/fqd.toml"
printf '[http]\nlisten = "127.0.0.1:0"\n' >>"$tmp/fqd.toml"
out=$(bash "$src/scripts/pod_resources.sh" "$tmp/stage/bin" "$tmp/fqd.toml" fandisk.ply --mesh-dir "$src/data" \
      --fps 2 -d 3 --warmup 0 --noise 0.2 2>&1)
line=$(grep '^fqd: ' <<<"$out") || { echo "$out"; echo "FAIL: no fqd: line" >&2; exit 1; }
echo "$line"
[[ $line =~ ^fqd:\ [0-9.]+\ cores\ over\ [0-9]+\ s,\ resident\ memory\ peak\ ([0-9]+)\ MiB.*engines\ busy\ ([0-9.]+)$ ]] ||
  { echo "FAIL: unexpected report: $line" >&2; exit 1; }
((BASH_REMATCH[1] > 1)) || { echo "FAIL: resident memory of ${BASH_REMATCH[1]} MiB" >&2; exit 1; }
[[ ${BASH_REMATCH[2]} != 0.00 ]] || { echo "FAIL: the engine was never busy" >&2; exit 1; }
