#!/usr/bin/env bash
# fqd's live viewer in real headless Chromium: fqd (CPU engine, HTTP on a free port, viewer
# from web/) and fqpub on the bundled fandisk, once per result form (stream "fandisk" in the
# default POSITIONS form, "fandisk_mesh" in the MESH form); viewer_check.mjs loads the page,
# waits for a frame, checks the canvas and the rising frame count, and saves a screenshot; the
# overlay must name the form shown. fqd has a token (http.token_file): the page is refused until
# the browser logs in at /login?token=..., then works on the cookie that sets.
#   viewer_test.sh FQD FQPUB SOURCE_DIR OUT_DIR
# Exit 77 (skipped) only when Chromium is absent.
set -euo pipefail
fqd=$1 fqpub=$2 src=$3 out=$4
if [[ ! -x /usr/bin/chromium ]]; then
  echo "SKIP: /usr/bin/chromium is not installed (scripts/setup-deps.sh installs Debian's chromium)"
  exit 77
fi
if [[ ! -f $src/web/node_modules/three/build/three.module.js || ! -d $src/web/node_modules/playwright-core ]]; then
  echo "FAIL: the viewer's npm packages are missing: run bash scripts/web-deps.sh" >&2
  exit 1
fi
mkdir -p "$out"
tmp=$(mktemp -d)
cleanup() {
  [[ -n ${pub:-} ]] && kill "$pub" 2>/dev/null || true
  [[ -n ${pub_mesh:-} ]] && kill "$pub_mesh" 2>/dev/null || true
  [[ -n ${daemon:-} ]] && kill "$daemon" 2>/dev/null && wait "$daemon" 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT
token=$(od -An -tx1 -N16 /dev/urandom | tr -d ' \n')
echo "$token" >"$tmp/token"
{ cat "$src/tests/daemon/child_fqd.toml"; cat <<TOML; } >"$tmp/fqd.toml"
[http]
listen = "127.0.0.1:0"
web_root = "$src/web"
token_file = "$tmp/token"
[streams.fandisk_mesh.output]
result_form = "mesh"
TOML
"$fqd" --config "$tmp/fqd.toml" --endpoints-file "$tmp/endpoints.json" &
daemon=$!
for _ in $(seq 300); do [[ -s $tmp/endpoints.json ]] && break; sleep 0.1; done
[[ -s $tmp/endpoints.json ]] || { echo "FAIL: fqd did not start" >&2; exit 1; }
field() { sed -E "s/.*\"$1\":\"([^\"]+)\".*/\1/" "$tmp/endpoints.json"; }
"$fqpub" "$src/data/fandisk.ply" --endpoint "$(field ingest)" --stream fandisk --fps 5 --noise 0.1 \
  --duration 240 --quiet &
pub=$!
"$fqpub" "$src/data/fandisk.ply" --endpoint "$(field ingest)" --stream fandisk_mesh --fps 5 --noise 0.1 \
  --duration 240 --quiet &
pub_mesh=$!
check() {  # STREAM FORM SCREENSHOT
  local result
  result=$(node "$src/tests/web/viewer_check.mjs" "$(field http)" "$1" "$3" --token "$token") ||
    { echo "$result"; return 1; }
  echo "$result"
  [[ $result == *"$2 form"* ]] || { echo "FAIL: the overlay of stream $1 does not say \"$2 form\"" >&2; return 1; }
}
check fandisk positions "$out/viewer.png"
check fandisk_mesh mesh "$out/viewer-mesh.png"
