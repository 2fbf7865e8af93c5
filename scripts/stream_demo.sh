#!/usr/bin/env bash
# Streaming demo: fqd on configs/fqd.toml (CPU engine when there is no GPU), fqpub publishing
# the bundled data/fandisk.ply with fresh noise for ~4 s at 2 fps on stream "demo" (its budget
# in configs/fqd.toml fits the CPU engine on 2 cores), fqsub receiving, checking and writing
# coloured PLYs. Prints fqsub's summary, a PLY path, and one line saying why when results
# were late; stops fqd with SIGINT.
# Usage: scripts/stream_demo.sh [BUILD_DIR]   (output folder: $FQ_DEMO_OUT/stream or a temp dir;
# FQ_DEMO_CONFIG: another fqd configuration, e.g. with free ports for a test)
# Exits non-zero when fqd does not start or stop cleanly, or fqsub saw a bad/error result.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${FQ_DEMO_OUT:+$FQ_DEMO_OUT/stream}
out=${out:-$(mktemp -d -t fq_stream_demo.XXXXXX)}
mkdir -p "$out"
config=${FQ_DEMO_CONFIG:-$root/configs/fqd.toml}
fqd="$build/daemon/fqd" fqpub="$build/clients/fqpub/fqpub" fqsub="$build/clients/fqsub/fqsub"
fqctl="$build/clients/fqctl/fqctl"
for exe in "$fqd" "$fqpub" "$fqsub" "$fqctl"; do
  [[ -x $exe ]] || { echo "stream_demo: $exe is missing (build first)" >&2; exit 1; }
done

# fqd prints its bound endpoints on stdout once it listens: read that line to know it is up.
coproc FQD { exec "$fqd" --config "$config" --print-endpoints 2>"$out/fqd.log"; }
fqd_pid=$FQD_PID
cleanup() { kill -0 "$fqd_pid" 2>/dev/null && kill -KILL "$fqd_pid" 2>/dev/null || true; }
trap cleanup EXIT
if ! read -r -t 30 endpoints <&"${FQD[0]}"; then
  echo "stream_demo: fqd did not start; its log:" >&2
  cat "$out/fqd.log" >&2
  exit 1
fi
endpoint() { sed -n "s/.*\"$1\":\"\([^\"]*\)\".*/\1/p" <<<"$endpoints"; }
ingest=$(endpoint ingest) publish=$(endpoint publish) control=$(endpoint control)
echo "fqd is up: ingest $ingest, publish $publish (log: $out/fqd.log)"

"$fqsub" --endpoint "$publish" --stream demo --idle-timeout 5 --duration 30 --write-every 4 \
  --faces "$root/data/fandisk.ply" --out "$out/ply" --quiet 2>"$out/fqsub.log" &
sub_pid=$!
"$fqpub" "$root/data/fandisk.ply" --endpoint "$ingest" --stream demo --fps 2 --duration 4 \
  --noise 0.2 --seed 1 --quiet
sub_rc=0
wait "$sub_pid" || sub_rc=$?
"$fqctl" --control "$control" counters demo --json >"$out/counters.json" 2>/dev/null || true
engines=$(sed -n 's/.*fqd: engines \[\([^]]*\)\].*/\1/p' "$out/fqd.log" | head -1)

kill -INT "$fqd_pid"
fqd_rc=0
wait "$fqd_pid" || fqd_rc=$?
trap - EXIT

echo "== fqsub summary =="
cat "$out/fqsub.log"
ply=$(sed -n 's/^fqsub: last PLY written: //p' "$out/fqsub.log")
[[ -n $ply ]] && echo "filtered + clustered frame (PLY with cluster colours): $ply"
# Late results get one line saying why, from fqd's own stage latencies.
/usr/bin/python3 - "$out/counters.json" "$config" "$engines" <<'PY'
import json, sys, tomllib
try:
    s = json.load(open(sys.argv[1]))["streams"][0]
except (OSError, ValueError, LookupError):
    sys.exit(0)
config = tomllib.load(open(sys.argv[2], "rb"))
budget = config.get("streams", {}).get("demo", {}).get("budget_ms", config.get("defaults", {}).get("budget_ms", 100))
p50 = lambda stage: s["stages"].get(stage, {}).get("p50_ms", 0)
if s["late"] == 0:
    print(f"stream_demo: no late result: {s['frames_out']} results within the {budget:g} ms budget "
          f"(engine {sys.argv[3]}: p50 {p50('engine'):.0f} ms a frame)")
else:
    print(f"stream_demo: {s['late']} of {s['frames_out']} results late because fqd's engine ({sys.argv[3]}) took "
          f"p50 {p50('engine'):.0f} ms a frame and frames waited p50 {p50('wait'):.0f} ms for it, against the "
          f"demo stream's budget of {budget:g} ms ([streams.demo] in configs/fqd.toml): this machine was busier "
          f"than that budget allows")
PY
echo "fqd exit status after SIGINT: $fqd_rc"
if [[ $sub_rc -ne 0 || $fqd_rc -ne 0 || -z $ply ]]; then
  echo "stream_demo: FAILED (fqsub $sub_rc, fqd $fqd_rc)" >&2
  exit 1
fi
echo "stream_demo: OK"
