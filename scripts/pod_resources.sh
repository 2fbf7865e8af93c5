#!/usr/bin/env bash
# What one fqd process uses under a stream load, for a pod's resource requests
# (deploy/k8s/statefulset.yaml): starts fqd as its own process on CONFIG (HTTP on a free port),
# runs fqstreambench --connect against it with the arguments given, samples fqd's /metrics
# every second meanwhile, and prints the CPU it used (process_cpu_seconds_total over the run,
# in cores), its peak and final resident memory (process_resident_memory_bytes), GPU memory and
# the engines' utilisation (fq_engine_busy_seconds_total).
#   scripts/pod_resources.sh BIN_DIR CONFIG FQSTREAMBENCH_ARGS...
# BIN_DIR holds fqd and fqstreambench (a build's, or a scripts/stage.sh folder's bin/ with its
# lib/ beside it). CONFIG's endpoints and [http] listen are replaced by free ports.
set -euo pipefail
bin=$1 config=$2
shift 2
[[ -d $bin/../lib ]] && export LD_LIBRARY_PATH="$(cd "$bin/../lib" && pwd)${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
tmp=$(mktemp -d)
fqd_pid=
trap '[[ -n $fqd_pid ]] && kill "$fqd_pid" 2>/dev/null; rm -rf "$tmp"' EXIT
sed -e 's|^\(ingest\|publish\|control\) = .*|\1 = "tcp://127.0.0.1:*"|' -e 's|^listen = .*|listen = "127.0.0.1:0"|' \
  "$config" >"$tmp/fqd.toml"
"$bin/fqd" --config "$tmp/fqd.toml" --endpoints-file "$tmp/endpoints.json" --log-level warn &
fqd_pid=$!
for _ in $(seq 300); do [[ -s $tmp/endpoints.json ]] && break; sleep 0.1; done
ep() { python3 -c "import json,sys; print(json.load(open('$tmp/endpoints.json'))['$1'])"; }
python3 - "$(ep http)/metrics" "$tmp/stop" >"$tmp/samples.txt" <<'PY' &
import os, re, sys, time, urllib.request
def metric(text, name):
    return sum(float(v) for v in re.findall(rf"^{name}(?:{{[^}}]*}})? (\S+)$", text, re.M))
while not os.path.exists(sys.argv[2]):
    t = urllib.request.urlopen(sys.argv[1], timeout=10).read().decode()
    print(time.time(), metric(t, "process_cpu_seconds_total"), metric(t, "process_resident_memory_bytes"),
          metric(t, "fq_gpu_memory_used_bytes"), metric(t, "fq_engine_busy_seconds_total"), flush=True)
    time.sleep(1)
PY
sampler=$!
"$bin/fqstreambench" --connect --ingest "$(ep ingest)" --publish "$(ep publish)" --control "$(ep control)" "$@"
touch "$tmp/stop"
wait "$sampler"
python3 - "$tmp/samples.txt" <<'PY'
import sys
rows = [list(map(float, l.split())) for l in open(sys.argv[1])]
(t0, cpu0, _, _, busy0), (t1, cpu1, rss1, gpu1, busy1) = rows[0], rows[-1]
span = t1 - t0
print(f"fqd: {(cpu1 - cpu0) / span:.2f} cores over {span:.0f} s, resident memory peak "
      f"{max(r[2] for r in rows) / 2**20:.0f} MiB (end {rss1 / 2**20:.0f} MiB), GPU memory used "
      f"{gpu1 / 2**20:.0f} MiB (device-wide), engines busy {(busy1 - busy0) / span:.2f}")
PY
