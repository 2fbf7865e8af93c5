#!/usr/bin/env bash
# The live viewer on the bundled sample: fqd on configs/fqd.toml (HTTP on 127.0.0.1:8080) and
# fqpub looping data/fandisk.ply with fresh noise at 2 fps on stream "demo", until Ctrl-C.
# Opens http://127.0.0.1:8080/?stream=demo in the desktop's browser when there is one
# (xdg-open), else prints the address to open.
# Usage: scripts/live_demo.sh [BUILD_DIR]   (FQ_DEMO_CONFIG: another fqd configuration)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
log=$(mktemp -t fq_live_demo.XXXXXX.log)
coproc FQD { exec "$build/daemon/fqd" --config "${FQ_DEMO_CONFIG:-$root/configs/fqd.toml}" --print-endpoints 2>"$log"; }
fqd_pid=$FQD_PID
pub_pid=
stop() {
  # fqpub first, so that it does not see fqd go away.
  [[ -n $pub_pid ]] && { kill -INT "$pub_pid" 2>/dev/null; wait "$pub_pid" 2>/dev/null; }
  kill -INT "$fqd_pid" 2>/dev/null
  wait 2>/dev/null || true
  echo "live_demo: stopped (fqd's log: $log)"
}
trap stop EXIT
trap 'exit 0' INT TERM
read -r -t 30 endpoints <&"${FQD[0]}" || { echo "live_demo: fqd did not start:" >&2; cat "$log" >&2; exit 1; }
http=$(sed -n 's/.*"http":"\([^"]*\)".*/\1/p' <<<"$endpoints")
ingest=$(sed -n 's/.*"ingest":"\([^"]*\)".*/\1/p' <<<"$endpoints")
[[ -n $http ]] || { echo "live_demo: configs/fqd.toml has no [http] listen" >&2; exit 1; }
"$build/clients/fqpub/fqpub" "$root/data/fandisk.ply" --endpoint "$ingest" --stream demo --fps 2 --noise 0.2 \
  --quiet &
pub_pid=$!
url="$http/?stream=demo"
echo "live_demo: fqd at $http, fqpub sending fandisk with noise on stream demo; Ctrl-C stops both"
if [[ -n ${DISPLAY:-}${WAYLAND_DISPLAY:-} ]] && command -v xdg-open >/dev/null; then
  xdg-open "$url" >/dev/null 2>&1 || true
  echo "live_demo: opened $url"
else
  echo "live_demo: open $url in a browser"
fi
wait "$pub_pid"
