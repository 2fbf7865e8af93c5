#!/usr/bin/env bash
# The demo (README command 1): scripts/demo.sh installs only what it runs (setup-deps.sh
# --build-only, which names no test-only package: tests/deploy/check_images.sh checks that list)
# and ends with the command that opens the live viewer; the streaming part, on configs/fqd.toml
# with free ports, publishes, receives and reports either no late result or one line saying
# why; the live viewer's script serves the viewer and the demo stream until stopped.
#   demo_test.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$1 build=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
demo=$src/scripts/demo.sh
grep -q 'scripts/setup-deps.sh" --build-only' "$demo" || fail "demo.sh does not install with setup-deps.sh --build-only"
grep -q -- '-DFQ_BUILD_TESTS=OFF' "$demo" || fail "demo.sh configures a new build folder with the tests"
[[ $(tail -1 "$demo") == 'echo "bash $root/scripts/live_demo.sh $build"' ]] || fail "demo.sh does not end with the viewer's command"

tmp=$(mktemp -d)
live_pid=
cleanup() { [[ -n $live_pid ]] && kill -TERM "$live_pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
# configs/fqd.toml with free ports (other tests and a running fqd may hold 5555-5557, 8080).
sed -e 's|tcp://127.0.0.1:555[567]|tcp://127.0.0.1:*|' -e 's|^listen = "127.0.0.1:8080"|listen = "127.0.0.1:0"|' \
    -e "s|^web_root = \"../web\"|web_root = \"$src/web\"|" "$src/configs/fqd.toml" >"$tmp/fqd.toml"
FQ_DEMO_CONFIG=$tmp/fqd.toml FQ_DEMO_OUT=$tmp/out bash "$src/scripts/stream_demo.sh" "$build" >"$tmp/stream.out" 2>&1 ||
  { cat "$tmp/stream.out"; fail "stream_demo.sh failed"; }
cat "$tmp/stream.out"
late=$(sed -n 's/^fqsub: .* late \([0-9]*\) .*/\1/p' "$tmp/stream.out")
[[ -n $late ]] || fail "no fqsub summary"
if ((late == 0)); then
  grep -q '^stream_demo: no late result: ' "$tmp/stream.out" || fail "no late result, but not said"
else
  [[ $(grep -c '^stream_demo: .* results late because ' "$tmp/stream.out") == 1 ]] || fail "$late late results without one line why"
fi

FQ_DEMO_CONFIG=$tmp/fqd.toml bash "$src/scripts/live_demo.sh" "$build" >"$tmp/live.out" 2>&1 &
live_pid=$!
for _ in $(seq 300); do grep -q 'open http\|opened http' "$tmp/live.out" && break; sleep 0.1; done
url=$(grep -o 'http://[^ ]*?stream=demo' "$tmp/live.out" | head -1)
[[ -n $url ]] || { cat "$tmp/live.out"; fail "live_demo.sh named no viewer address"; }
/usr/bin/python3 - "$url" <<'PY'
import json, sys, time, urllib.request
url = sys.argv[1]
base = url.split("/?")[0]
assert b"importmap" in urllib.request.urlopen(url, timeout=30).read()
for _ in range(300):  # the demo stream appears once fqpub's first frame arrived
    streams = json.load(urllib.request.urlopen(base + "/streams", timeout=30))["streams"]
    if any(s["stream"] == "demo" and s["frames_in"] > 0 for s in streams):
        break
    time.sleep(0.1)
else:
    sys.exit(f"no frames of stream demo at {base}/streams")
print(f"live_demo: {url} serves the viewer and stream demo")
PY
kill -TERM "$live_pid"
wait "$live_pid" || fail "live_demo.sh exited $? on SIGTERM"
live_pid=
grep -q '^live_demo: stopped' "$tmp/live.out" || fail "live_demo.sh did not stop fqd and fqpub"
echo "demo: OK"
