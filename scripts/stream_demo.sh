#!/usr/bin/env bash
# Streaming demo: fqd on configs/fqd.toml (CPU engine when there is no GPU), fqpub publishing
# the bundled data/fandisk.ply with fresh noise for ~3 s, fqsub receiving, checking and
# writing coloured PLYs. Prints fqsub's summary and a PLY path; stops fqd with SIGINT.
# Usage: scripts/stream_demo.sh [BUILD_DIR]   (output folder: $FQ_DEMO_OUT/stream or a temp dir)
# Exits non-zero when fqd does not start or stop cleanly, or fqsub saw a bad/error result.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${FQ_DEMO_OUT:+$FQ_DEMO_OUT/stream}
out=${out:-$(mktemp -d -t fq_stream_demo.XXXXXX)}
mkdir -p "$out"
fqd="$build/daemon/fqd" fqpub="$build/clients/fqpub/fqpub" fqsub="$build/clients/fqsub/fqsub"
for exe in "$fqd" "$fqpub" "$fqsub"; do
  [[ -x $exe ]] || { echo "stream_demo: $exe is missing (build first)" >&2; exit 1; }
done

# fqd prints its bound endpoints on stdout once it listens: read that line to know it is up.
coproc FQD { exec "$fqd" --config "$root/configs/fqd.toml" --print-endpoints 2>"$out/fqd.log"; }
fqd_pid=$FQD_PID
cleanup() { kill -0 "$fqd_pid" 2>/dev/null && kill -KILL "$fqd_pid" 2>/dev/null || true; }
trap cleanup EXIT
if ! read -r -t 30 endpoints <&"${FQD[0]}"; then
  echo "stream_demo: fqd did not start; its log:" >&2
  cat "$out/fqd.log" >&2
  exit 1
fi
endpoint() { sed -n "s/.*\"$1\":\"\([^\"]*\)\".*/\1/p" <<<"$endpoints"; }
ingest=$(endpoint ingest) publish=$(endpoint publish)
echo "fqd is up: ingest $ingest, publish $publish (log: $out/fqd.log)"

"$fqsub" --endpoint "$publish" --stream demo --idle-timeout 5 --duration 30 --write-every 5 \
  --faces "$root/data/fandisk.ply" --out "$out/ply" --quiet 2>"$out/fqsub.log" &
sub_pid=$!
"$fqpub" "$root/data/fandisk.ply" --endpoint "$ingest" --stream demo --fps 3 --duration 3 \
  --noise 0.2 --seed 1 --quiet
sub_rc=0
wait "$sub_pid" || sub_rc=$?

kill -INT "$fqd_pid"
fqd_rc=0
wait "$fqd_pid" || fqd_rc=$?
trap - EXIT

echo "== fqsub summary =="
cat "$out/fqsub.log"
ply=$(sed -n 's/^fqsub: last PLY written: //p' "$out/fqsub.log")
[[ -n $ply ]] && echo "filtered + clustered frame (PLY with cluster colours): $ply"
echo "fqd exit status after SIGINT: $fqd_rc"
if [[ $sub_rc -ne 0 || $fqd_rc -ne 0 || -z $ply ]]; then
  echo "stream_demo: FAILED (fqsub $sub_rc, fqd $fqd_rc)" >&2
  exit 1
fi
echo "stream_demo: OK"
